// Where the page's data comes from (studio/PROTOCOL.md): a recording embedded in the page
// (window.COBRA_RECORDING, from recording.js beside index.html: replay from the file system with
// no server), or the cobra server's /api/model, /api/recording and WebSocket /ws.

/** The token from the page's URL (?token=...), sent with every request; the server's cookie
 *  covers requests too, the header makes the page independent of cookie settings. */
export function pageToken() {
  return new URLSearchParams(window.location.search).get('token') ?? '';
}

function apiUrl(path) {
  const url = new URL(path, window.location.href);
  const token = pageToken();
  if (token) url.searchParams.set('token', token);
  return url;
}

const LOADING_RETRY_MS = 250;
const LOADING_LIMIT_MS = 120000; // how long the page waits for a run that is still loading

/**
 * GETs a JSON document; a non-2xx answer throws an Error with the server's `error` text. HTTP 503
 * (the run is still loading) is asked again every LOADING_RETRY_MS for up to LOADING_LIMIT_MS.
 */
async function getJson(path) {
  let response;
  const start = Date.now();
  for (;;) {
    try {
      response = await fetch(apiUrl(path), { headers: { 'X-Cobra-Token': pageToken() } });
    } catch (err) {
      throw new Error(`${path}: the cobra server cannot be reached (${err.message})`, { cause: err });
    }
    if (response.status !== 503 || Date.now() - start > LOADING_LIMIT_MS) break;
    await new Promise((resolve) => setTimeout(resolve, LOADING_RETRY_MS));
  }
  const text = await response.text();
  let body;
  try {
    body = JSON.parse(text);
  } catch {
    throw new Error(`${path}: HTTP ${response.status}: expected JSON, got ${JSON.stringify(text.slice(0, 120))}`);
  }
  if (!response.ok || body.error) {
    const err = new Error(`${path}: HTTP ${response.status}: ${body.error ?? 'no error text'}`);
    err.status = response.status;
    err.serverError = body.error;
    throw err;
  }
  return body;
}

/** Loads recording.js beside index.html (file:// replay), resolving once it ran. */
function loadRecordingScript() {
  return new Promise((resolve, reject) => {
    const script = document.createElement('script');
    script.src = 'recording.js';
    script.onload = resolve;
    script.onerror = () => reject(new Error('recording.js: not found beside index.html (open a run folder\'s studio/index.html, or start `cobra studio RUN_DIR`)'));
    document.head.append(script);
  });
}

function checkRecording(rec, where) {
  if (!rec || typeof rec !== 'object' || !rec.model || !Array.isArray(rec.frames)) {
    throw new Error(`${where}: expected { model, frames: [...], events: [...] }`);
  }
  return { model: rec.model, frames: rec.frames, events: rec.events ?? [], end: rec.end ?? null };
}

/**
 * Resolves to { model, replay } where replay = { frames, events, end } in replay mode (end: how
 * the run ended, or null for a recording without it), else null.
 * Throws an Error whose message names the failing source.
 */
export async function loadSession() {
  if (!window.COBRA_RECORDING && window.location.protocol === 'file:') await loadRecordingScript();
  if (window.COBRA_RECORDING) {
    const rec = checkRecording(window.COBRA_RECORDING, 'window.COBRA_RECORDING');
    return { model: { ...rec.model, mode: 'replay' }, replay: rec };
  }
  let model;
  try {
    model = await getJson('api/model');
  } catch (err) {
    // The run could not start (a bad application file, an unknown port of its studio table): the
    // page shows the very line `cobra run` printed on the command line.
    if (err.status === 500 && err.serverError) throw new Error(`cobra: ${err.serverError}`, { cause: err });
    throw err;
  }
  if (model.protocol !== 1) throw new Error(`api/model: protocol ${model.protocol}, expected 1`);
  if (model.mode !== 'replay') return { model, replay: null };
  const rec = await getJson('api/recording');
  if (!Array.isArray(rec.frames)) throw new Error('api/recording: expected { "frames": [...] }');
  return { model, replay: { frames: rec.frames, events: rec.events ?? [], end: rec.end ?? null } };
}

/**
 * A live run's history (GET api/recording): { frames, events }, the newest frames and events the
 * server streamed before this page came (bounded: studio/PROTOCOL.md, "History").
 */
export async function loadHistory() {
  const history = await getJson('api/recording');
  return { frames: Array.isArray(history.frames) ? history.frames : [], events: Array.isArray(history.events) ? history.events : [] };
}

/**
 * The live connection: calls handlers.frame(msg), .event(msg), .end(msg), .error(msg) per server
 * message (by its type) and handlers.closed(reason) once when the socket closes before the run's
 * end. Inputs go by POST (postInput), whose answer carries the server's error text.
 */
export function connectLive(handlers) {
  const url = apiUrl('ws');
  url.protocol = url.protocol === 'https:' ? 'wss:' : 'ws:';
  const socket = new WebSocket(url);
  let ended = false;
  socket.onmessage = (ev) => {
    let msg;
    try {
      msg = JSON.parse(ev.data);
    } catch {
      handlers.closed(`/ws: a message that is not JSON: ${String(ev.data).slice(0, 80)}`);
      return;
    }
    if (msg.type === 'end') ended = true;
    handlers[msg.type]?.(msg);
  };
  socket.onclose = (ev) => {
    if (!ended) handlers.closed(`/ws: the connection to the cobra server closed (code ${ev.code}${ev.reason ? `: ${ev.reason}` : ''}); the view is stopped`);
  };
}

/** POSTs a surgeon's input; throws an Error with the server's error text on failure. */
export async function postInput(name) {
  const response = await fetch(apiUrl('api/input'), {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', 'X-Cobra-Token': pageToken() },
    body: JSON.stringify({ name }),
  });
  if (!response.ok) {
    const body = await response.json().catch(() => ({}));
    throw new Error(`api/input '${name}': HTTP ${response.status}: ${body.error ?? 'no error text'}`);
  }
}
