// A rolling plot on a canvas: the last `span` seconds of board time, one or more series.
"use strict";

class Plot {
  constructor(canvas, series, span_s, min_range) {
    this.canvas = canvas;
    this.min_range = min_range;  // a flat line stays flat, not noise blown up to the full height
    this.series = series;  // [{color, dashed}]
    this.span = span_s * 1e6;
    this.points = series.map(() => []);  // per series: [[t_us, value], ...]
  }

  add(index, t_us, value) {
    const p = this.points[index];
    p.push([t_us, value]);
    while (p.length > 0 && p[0][0] < t_us - this.span) p.shift();
  }

  draw() {
    const c = this.canvas, ctx = c.getContext("2d");
    const w = c.clientWidth, h = c.clientHeight;
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    ctx.clearRect(0, 0, w, h);
    let lo = Infinity, hi = -Infinity, end = -Infinity;
    for (const p of this.points) for (const [t, v] of p) {
      lo = Math.min(lo, v); hi = Math.max(hi, v); end = Math.max(end, t);
    }
    if (end === -Infinity) return;
    if (hi - lo < this.min_range) {
      const mid = (hi + lo) / 2;
      hi = mid + this.min_range / 2; lo = mid - this.min_range / 2;
    }
    const pad = (hi - lo) * 0.1; lo -= pad; hi += pad;
    const x = (t) => w - (end - t) / this.span * w, y = (v) => h - (v - lo) / (hi - lo) * h;
    ctx.fillStyle = "#888"; ctx.font = "10px sans-serif";
    ctx.fillText(hi.toPrecision(3), 2, 10); ctx.fillText(lo.toPrecision(3), 2, h - 2);
    this.series.forEach((s, i) => {
      ctx.strokeStyle = s.color; ctx.setLineDash(s.dashed ? [4, 3] : []); ctx.beginPath();
      this.points[i].forEach(([t, v], k) => (k ? ctx.lineTo(x(t), y(v)) : ctx.moveTo(x(t), y(v))));
      ctx.stroke();
    });
  }
}
