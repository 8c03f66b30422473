// cobra studio's page: loads the session (live server, replay server, or recording.js from the
// file system), builds the 3D view and the console, then follows the WebSocket (live) or the
// timeline (replay). Exposes window.cobraStudio for tests.
import 'uplot/dist/uPlot.min.css';
import './style.css';
import { loadSession, loadHistory, connectLive, pageToken, postInput } from './source.js';
import { StudioView } from './scene.js';
import { Panel } from './panel.js';
import { Plots } from './plots.js';
import { Trails } from './trails.js';

// The deployment editor (editor.html) is served beside this page by cobra's server (not from file://).
if (window.location.protocol.startsWith('http')) {
  const editorLink = document.getElementById('editor-link');
  if (pageToken()) editorLink.href = `editor.html?token=${encodeURIComponent(pageToken())}`;
  editorLink.hidden = false;
}

/**
 * Shows `message` in the page's error banner (errors stay visible until the page reloads; one
 * that repeats, as a bad frame would every frame, is shown once).
 */
function showError(message) {
  const banner = document.getElementById('error');
  if ([...banner.children].some((line) => line.textContent === message)) return;
  const line = document.createElement('div');
  line.textContent = message;
  banner.append(line);
  banner.hidden = false;
}

/** Index of the last frame with t <= time (frames sorted by t); 0 before the first. */
function frameIndexAt(frames, time) {
  let lo = 0;
  let hi = frames.length - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (frames[mid].t <= time) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

/**
 * Per chart, the time it entered the state before the one it is in at frames[index] (the start of
 * the previous run of equal states; the first frame's time when there is none).
 */
function previousEntries(frames, index, charts) {
  const since = {};
  for (const { name } of charts) {
    let i = index;
    for (let run = 0; run < 2; run += 1) {
      const state = frames[i].charts?.[name];
      while (i > 0 && frames[i - 1].charts?.[name] === state) i -= 1;
      if (run === 0 && i > 0) i -= 1;
    }
    since[name] = frames[i].t;
  }
  return since;
}

function startReplay(replay, view, panel, plots, trails, state, model) {
  const { frames, events } = replay;
  if (frames.length === 0) throw new Error('recording: no frames (the run recorded nothing)');
  for (const e of events) panel.addEvent(e);
  // How the run ended: the recording's `end` (older recordings: an end message among the events).
  const end = replay.end ?? events.find((e) => e.type === 'end');
  if (replay.end) panel.addEvent(replay.end);
  plots.setFrames(frames);
  trails.setFrames(frames);
  const slider = document.getElementById('scrub');
  const label = document.getElementById('scrub-time');
  const play = document.getElementById('play');
  document.getElementById('timeline').hidden = false;
  slider.max = String(frames.length - 1);
  const show = (index) => {
    const frame = frames[index];
    state.frame = frame;
    trails.draw(view, index);
    view.applyFrame(frame);
    panel.showFrame(frame, previousEntries(frames, index, model.charts ?? []));
    // The last frame is the end of the timeline: the run ended there (its end time may fall
    // between two recorded frames).
    const last = index === frames.length - 1;
    panel.showEventsUntil(last && end ? Math.max(frame.t, end.t ?? frame.t) : frame.t, end);
    plots.setCursor(frame.t);
    label.textContent = `${frame.t.toFixed(2)} / ${frames.at(-1).t.toFixed(2)} s`;
  };
  slider.addEventListener('input', () => {
    try {
      show(Number(slider.value));
    } catch (err) {
      showError(err.message);
    }
  });
  state.seek = (t) => {
    const index = frameIndexAt(frames, t);
    slider.value = String(index);
    show(index);
    return frames[index].t;
  };
  let timer = null;
  play.addEventListener('click', () => {
    if (timer) {
      clearInterval(timer);
      timer = null;
      play.textContent = 'Play';
      return;
    }
    play.textContent = 'Pause';
    const t0 = performance.now() / 1000 - state.frame.t + (Number(slider.value) >= frames.length - 1 ? frames.at(-1).t : 0);
    timer = setInterval(() => {
      const index = frameIndexAt(frames, performance.now() / 1000 - t0);
      slider.value = String(index);
      show(index);
      if (index >= frames.length - 1) play.click();
    }, 1000 / 30);
  });
  show(0);
}

/**
 * Live: every frame's signals go to the plots, but the view and the console show only the newest
 * frame, once per animation frame, so a page slower than the stream skips frames instead of
 * queueing them (the server does the same per client).
 */
function startLive(view, panel, plots, trails, state, model) {
  let newest = null;
  // Per chart: its state, when it entered it and when it entered the one before.
  const entries = Object.fromEntries((model.charts ?? []).map((c) => [c.name, { state: undefined, at: 0, before: 0 }]));
  const show = () => {
    const frame = newest;
    newest = null;
    state.frame = frame;
    try {
      trails.draw(view);
      view.applyFrame(frame);
      panel.showFrame(frame, Object.fromEntries(Object.entries(entries).map(([name, e]) => [name, e.before])));
    } catch (err) {
      showError(err.message);
    }
  };
  // The run's time only goes forward: a frame at or before the newest one applied (the history's,
  // then the socket's) is a copy or stale, and would fold the plots back on themselves.
  let newestT = -Infinity;
  const frame = (msg) => {
    if (!(msg.t > newestT)) return;
    newestT = msg.t;
    for (const [name, e] of Object.entries(entries)) {
      if (msg.charts?.[name] === e.state) continue;
      Object.assign(e, { state: msg.charts?.[name], before: e.at, at: msg.t });
    }
    if (newest === null) requestAnimationFrame(show);
    newest = msg;
    plots.addFrame(msg);
    trails.addFrame(msg);
  };
  const handlers = {
    frame,
    event: (msg) => panel.addEvent(msg),
    end: (msg) => panel.addEvent(msg),
    error: (msg) => showError(`/ws: ${msg.error}`),
    closed: showError,
  };
  // A page that comes mid-run first takes the run's history (the events so far, the plots' and
  // trails' frames): the socket opens at once and what it brings meanwhile waits, then only what
  // the history does not hold is applied (frames after its last: frame() drops the others; events
  // it lacks).
  let waiting = [];
  connectLive(Object.fromEntries(Object.entries(handlers).map(([type, handle]) => [type, (msg) => {
    if (waiting) waiting.push([handle, msg]);
    else handle(msg);
  }])));
  const replayWaiting = (history) => {
    const seen = new Set(history.events.map((e) => JSON.stringify(e)));
    for (const f of history.frames) frame(f);
    for (const e of history.events) panel.addEvent(e);
    for (const [handle, msg] of waiting.splice(0)) {
      if (msg.type === 'event' && seen.has(JSON.stringify(msg))) continue;
      handle(msg);
    }
    waiting = null;
  };
  loadHistory().then(replayWaiting, (err) => {
    showError(`${err.message}: the run's history is not shown`);
    replayWaiting({ frames: [], events: [] });
  });
}

async function main() {
  const state = { frame: null, seek: null };
  let session;
  try {
    session = await loadSession();
  } catch (err) {
    showError(err.message);
    return;
  }
  const { model, replay } = session;
  try {
    const view = new StudioView(document.getElementById('view'), model, showError);
    const panel = new Panel(document, model);
    const plots = new Plots(document.getElementById('signal-list'), document.getElementById('plots'), model.signals ?? []);
    panel.addInputs(postInput, showError);
    for (const entry of view.legend()) {
      const li = document.createElement('li');
      const swatch = document.createElement('span');
      swatch.style.background = entry.color;
      li.append(swatch, `${entry.name} (${entry.kind})`);
      document.getElementById('legend').append(li);
    }
    document.getElementById('plots-section').hidden = (model.signals ?? []).length === 0;
    document.getElementById('fit').addEventListener('click', () => {
      view.fitCamera();
      view.render();
    });
    window.cobraStudio = {
      scene: view.scene,
      model,
      linkObject: (robot, index) => view.linkObject(robot, index),
      frameTime: () => state.frame?.t ?? null,
      /** Replay: shows the last frame at or before `t` [s] and returns its time; live: null. */
      seek: (t) => state.seek?.(t) ?? null,
      /** Camera at `position` looking at `target` ([x,y,z] m). */
      setCamera: (position, target) => view.setCamera(position, target),
      /** Replay: the recording's events (the log's source); live: []. */
      events: replay?.events ?? [],
      /** The times [s] of the frames the plots hold (live: the history, then the stream). */
      plotTimes: () => [...plots.times],
      /** Replay: how the run ended (the recording's end), else null. */
      end: replay?.end ?? null,
    };
    const trails = new Trails(model);
    if (replay) startReplay(replay, view, panel, plots, trails, state, model);
    else startLive(view, panel, plots, trails, state, model);
  } catch (err) {
    showError(err.message);
  }
}

main();
