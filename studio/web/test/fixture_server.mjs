// A tiny stand-in for cobra's studio server (studio/PROTOCOL.md) for the browser tests and the
// screenshot script: serves dist/ and the fixture model/recording, checks the token like the real
// server, answers inputs and streams the recording's frames over /ws at 30 Hz.
//   mode 'live':   /api/model is fixtures/model.json, /ws streams frames (looping); the input
//                  'needle_mounted' switches the 'needle' chart to 'Mounted' and sends an event.
//   mode 'replay': /api/model is the recording's model, /api/recording its frames and events
//                  (live modes: an empty history).
//   mode 'error':  /api/model answers 500 { error }.
//   mode 'drop':   like live, but the server closes every WebSocket after its first frame.
//   mode 'wserror': like live, but the server also sends a WebSocket { type: 'error' } message.
//   mode 'loading': like live, but /api/model answers 503 (the run is loading) 3 times first.
import { createServer } from 'node:http';
import { readFileSync, existsSync } from 'node:fs';
import { dirname, join, extname, normalize, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { WebSocketServer } from 'ws';

const here = dirname(fileURLToPath(import.meta.url));
/** The built page: $COBRA_STUDIO_WEB_DIST (CTest passes the build tree's), else studio/web/dist. */
export const DIST = resolve(process.env.COBRA_STUDIO_WEB_DIST ?? join(here, '..', 'dist'));
export const FIXTURES = join(here, 'fixtures');
export const TOKEN = '0123456789abcdef0123456789abcdef';
export const MODEL_ERROR = "app 'fixture': studio table names port 'arm.nope', which the app does not have";
export const WS_ERROR = "no input 'x': expected one of needle_mounted, cryo_done";
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.txt': 'text/plain' };

export function loadFixtures() {
  return {
    liveModel: JSON.parse(readFileSync(join(FIXTURES, 'model.json'), 'utf8')),
    recording: JSON.parse(readFileSync(join(FIXTURES, 'recording.json'), 'utf8')),
  };
}

export function json(res, status, body) {
  res.writeHead(status, { 'Content-Type': 'application/json' });
  res.end(JSON.stringify(body));
}

/** The token of a request: query `token=`, header X-Cobra-Token or cookie, as cobra's server takes it. */
export function tokenOf(req, url) {
  const cookie = /(?:^|;\s*)cobra_token=([0-9a-f]+)/.exec(req.headers.cookie ?? '');
  return url.searchParams.get('token') ?? req.headers['x-cobra-token'] ?? cookie?.[1] ?? '';
}

/** Starts the server on 127.0.0.1 (any free port); resolves to { url, inputs, close() }. */
export async function startFixtureServer(mode = 'live') {
  const { liveModel, recording } = loadFixtures();
  const inputs = []; // names received, by POST or WebSocket, in order
  let needle = 'WaitMounted';
  let loading = mode === 'loading' ? 3 : 0;
  const sockets = new Set();
  const accept = (name) => {
    if (!liveModel.inputs.some((i) => i.name === name)) {
      return `no input '${name}': expected one of ${liveModel.inputs.map((i) => i.name).join(', ')}`;
    }
    inputs.push(name);
    if (name === 'needle_mounted') {
      needle = 'Mounted';
      for (const ws of sockets) ws.send(JSON.stringify({ type: 'event', t: 0, source: 'needle', name: 'e_needle_mounted' }));
    }
    return null;
  };
  const server = createServer((req, res) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    if (tokenOf(req, url) !== TOKEN) return json(res, 403, { error: 'missing or wrong token' });
    if (url.pathname === '/api/model') {
      if (mode === 'error') return json(res, 500, { error: MODEL_ERROR });
      if (loading > 0) {
        loading -= 1;
        return json(res, 503, { error: 'the run is loading; ask again' });
      }
      return json(res, 200, mode === 'replay' ? recording.model : liveModel);
    }
    if (url.pathname.startsWith('/api/mesh/')) {
      const file = join(FIXTURES, 'meshes', url.pathname.slice('/api/mesh/'.length).replace(/[^a-z_]/g, ''));
      if (!existsSync(file)) return json(res, 404, { error: `no mesh ${url.pathname}` });
      res.writeHead(200, { 'Content-Type': 'application/octet-stream' });
      return res.end(readFileSync(file));
    }
    if (url.pathname === '/api/recording') {
      // A live server's history (what it streamed before the page came): none here, the stream starts with the page.
      return json(res, 200, mode === 'replay' ? { frames: recording.frames, events: recording.events } : { frames: [], events: [] });
    }
    if (url.pathname === '/api/input' && req.method === 'POST') {
      let body = '';
      req.on('data', (chunk) => { body += chunk; });
      req.on('end', () => {
        if (mode === 'replay') return json(res, 409, { error: 'replay: no inputs' });
        const error = accept(JSON.parse(body).name);
        return error ? json(res, 400, { error }) : json(res, 200, { ok: true });
      });
      return undefined;
    }
    const file = normalize(join(DIST, url.pathname === '/' ? 'index.html' : url.pathname));
    if (!file.startsWith(DIST) || !existsSync(file)) return json(res, 404, { error: `no file ${url.pathname}` });
    const headers = { 'Content-Type': TYPES[extname(file)] ?? 'application/octet-stream' };
    if (url.pathname === '/') headers['Set-Cookie'] = `cobra_token=${TOKEN}; HttpOnly; SameSite=Strict`;
    res.writeHead(200, headers);
    return res.end(readFileSync(file));
  });
  const wss = new WebSocketServer({ noServer: true });
  server.on('upgrade', (req, socket, head) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    if (url.pathname !== '/ws' || tokenOf(req, url) !== TOKEN) {
      socket.end('HTTP/1.1 403 Forbidden\r\n\r\n');
      return;
    }
    wss.handleUpgrade(req, socket, head, (ws) => {
      sockets.add(ws);
      let index = 0;
      const timer = setInterval(() => {
        const frame = recording.frames[index % recording.frames.length];
        index += 1;
        ws.send(JSON.stringify({ ...frame, charts: { ...frame.charts, needle } }));
        if (mode === 'drop') ws.close(1011, 'fixture server dropped the connection');
        if (mode === 'wserror' && index === 1) ws.send(JSON.stringify({ type: 'error', error: WS_ERROR }));
      }, 1000 / 30);
      ws.on('message', (data) => {
        const msg = JSON.parse(String(data));
        if (msg.type === 'input') accept(msg.name);
      });
      ws.on('close', () => {
        clearInterval(timer);
        sockets.delete(ws);
      });
    });
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  const url = `http://127.0.0.1:${server.address().port}/`;
  return {
    url,
    modelRequestsLeftLoading: () => loading,
    pageUrl: `${url}?token=${TOKEN}`,
    inputs,
    close: () => closeServer(server, wss, sockets),
  };
}

/** Ends a fixture server: its websockets, the websocket server, then the HTTP server. */
export function closeServer(server, wss, sockets) {
  return new Promise((resolve) => {
    for (const ws of sockets) ws.terminate();
    wss.close();
    server.closeAllConnections();
    server.close(resolve);
  });
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const server = await startFixtureServer(process.argv[2] ?? 'live');
  console.log(`fixture studio: ${server.pageUrl}`);
}
