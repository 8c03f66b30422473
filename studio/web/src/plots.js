// Live and replay plots of the model's signals (uPlot), one plot per signal the user ticks.
// Live: the signals of the frames received so far (the newest LIVE_POINTS). Replay: the whole
// recording, with a vertical line at the timeline's time.
import uPlot from 'uplot';

const LIVE_POINTS = 30 * 120; // 2 min of frames at the protocol's 30 Hz

export class Plots {
  /** `list` holds the checkboxes, `container` the plots; `signals` is model.signals. */
  constructor(list, container, signals) {
    this.container = container;
    this.signals = signals;
    this.times = [];
    this.values = new Map(signals.map((s) => [s.name, []]));
    this.plots = new Map();
    this.cursorTime = null;
    this.pending = false;
    for (const [index, signal] of signals.entries()) {
      const label = document.createElement('label');
      const box = document.createElement('input');
      box.type = 'checkbox';
      box.name = signal.name;
      box.checked = index === 0;
      box.addEventListener('change', () => (box.checked ? this.show(signal) : this.hide(signal.name)));
      label.append(box, ` ${signal.name} [${signal.unit}]`);
      list.append(label);
    }
    if (signals.length > 0) this.show(signals[0]);
  }

  /** Replaces the data with a whole recording's frames. */
  setFrames(frames) {
    this.times = frames.map((f) => f.t);
    for (const [name, column] of this.values) {
      column.length = 0;
      for (const f of frames) column.push(f.signals?.[name] ?? null);
    }
    this.redraw();
  }

  /** Appends one live frame, dropping the oldest past LIVE_POINTS; redraws once per animation frame. */
  addFrame(frame) {
    this.times.push(frame.t);
    for (const [name, column] of this.values) column.push(frame.signals?.[name] ?? null);
    if (this.times.length > LIVE_POINTS) {
      this.times.shift();
      for (const column of this.values.values()) column.shift();
    }
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.redraw();
    });
  }

  /** Replay: moves the time marker to `t` [s]. */
  setCursor(t) {
    this.cursorTime = t;
    for (const plot of this.plots.values()) plot.redraw(false, false);
  }

  show(signal) {
    const width = Math.max(this.container.clientWidth, 200);
    const marker = {
      hooks: {
        draw: [(u) => {
          if (this.cursorTime === null) return;
          const x = u.valToPos(this.cursorTime, 'x', true);
          const ctx = u.ctx;
          ctx.save();
          ctx.strokeStyle = '#ffb347';
          ctx.lineWidth = 2;
          ctx.beginPath();
          ctx.moveTo(x, u.bbox.top);
          ctx.lineTo(x, u.bbox.top + u.bbox.height);
          ctx.stroke();
          ctx.restore();
        }],
      },
    };
    const opts = {
      title: `${signal.name} [${signal.unit}]`,
      width, height: 150,
      scales: { x: { time: false } },
      axes: [{ stroke: '#9fb3c8', grid: { stroke: '#30363e' } }, { stroke: '#9fb3c8', grid: { stroke: '#30363e' } }],
      series: [{ label: 't [s]' }, { label: signal.name, stroke: '#4e9ad8', width: 1.5, spanGaps: true }],
      plugins: [marker],
    };
    const div = document.createElement('div');
    div.dataset.signal = signal.name;
    this.container.append(div);
    this.plots.set(signal.name, new uPlot(opts, [this.times, this.values.get(signal.name)], div));
  }

  hide(name) {
    const plot = this.plots.get(name);
    if (!plot) return;
    plot.root.parentElement.remove();
    plot.destroy();
    this.plots.delete(name);
  }

  redraw() {
    for (const [name, plot] of this.plots) plot.setData([this.times, this.values.get(name)]);
  }
}
