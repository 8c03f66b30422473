// The trails of the 'points' extras (a tool's commanded and measured points, say): where each
// one's first point was over time, so nominal and actual paths show as lines (thesis Fig. 6.7).
// Replay: the recorded frames up to the timeline's frame; live: the frames received so far.

const LIVE_TRAIL_POINTS = 30 * 600; // 10 min at the protocol's 30 frames per s

const firstPoint = (frame, name) => {
  const p = frame.extras?.[name]?.points?.[0];
  return Array.isArray(p) && p.length === 3 && p.every(Number.isFinite) ? p : null;
};

export class Trails {
  constructor(model) {
    this.names = (model.extras ?? []).filter((e) => e.kind === 'points').map((e) => e.name);
    this.live = new Map(this.names.map((n) => [n, []]));
    this.recorded = null; // replay: per name, per frame index the point or null
  }

  /** Replay: indexes a recording's frames. */
  setFrames(frames) {
    this.recorded = new Map(this.names.map((n) => [n, frames.map((f) => firstPoint(f, n))]));
  }

  /** Live: appends one frame's points (the oldest dropped past LIVE_TRAIL_POINTS). */
  addFrame(frame) {
    for (const [name, trail] of this.live) {
      const p = firstPoint(frame, name);
      if (!p) continue;
      trail.push(p);
      if (trail.length > LIVE_TRAIL_POINTS) trail.shift();
    }
  }

  /** Draws every trail in `view`: up to frame `index` of the recording, or all live points. */
  draw(view, index) {
    for (const name of this.names) {
      const points = this.recorded ? this.recorded.get(name).slice(0, index + 1).filter((p) => p) : this.live.get(name);
      view.setTrail(name, points);
    }
  }
}
