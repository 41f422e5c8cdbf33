// A small software viewer on a 2D canvas, for the CPU backend (the WebGPU one draws with the
// wgpu viewer in the worker): flat-shaded triangles (painter's order), the wireframe over them
// and the input points (over the mesh too, unless turned off). Camera operations come from controls.js.
export class Viewer2D {
  constructor(canvas) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.mesh = null;
    this.points = null;
    this.pointsOverlay = true;
    this.yaw = 0.7;
    this.pitch = 0.45;
    this.scale = 1;
    this.offset = [0, 0];
    this.draw();
  }

  setPoints(points) {
    this.points = points;
    this.fit();
  }

  /** Whether the input points are drawn over the mesh too (they always show without one). */
  setPointsOverlay(on) {
    this.pointsOverlay = on;
    this.draw();
  }

  setMesh(positions, indices) {
    this.mesh = positions ? { positions, indices } : null;
    this.fit();
  }

  fit() {
    const src = this.mesh?.positions ?? this.points;
    if (!src || src.length < 3) return this.draw();
    const lo = [Infinity, Infinity, Infinity];
    const hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < src.length; i += 3) {
      for (let k = 0; k < 3; k++) {
        lo[k] = Math.min(lo[k], src[i + k]);
        hi[k] = Math.max(hi[k], src[i + k]);
      }
    }
    this.center = lo.map((l, k) => (l + hi[k]) / 2);
    this.radius = Math.max(1e-9, Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2);
    this.scale = 1;
    this.offset = [0, 0];
    this.draw();
  }

  orbit(dx, dy) {
    this.yaw += dx;
    this.pitch = Math.max(-1.5, Math.min(1.5, this.pitch + dy));
    this.draw();
  }

  pan(dx, dy) {
    this.offset[0] += dx;
    this.offset[1] += dy;
    this.draw();
  }

  zoom(factor) {
    this.scale *= factor;
    this.draw();
  }

  #project(x, y, z) {
    const [cx, cy, cz] = this.center ?? [0, 0, 0];
    x -= cx; y -= cy; z -= cz;
    const cyw = Math.cos(this.yaw), syw = Math.sin(this.yaw);
    const cp = Math.cos(this.pitch), sp = Math.sin(this.pitch);
    const x1 = cyw * x + syw * z;
    const z1 = -syw * x + cyw * z;
    const y2 = cp * y - sp * z1;
    const z2 = sp * y + cp * z1;
    const { width: w, height: h } = this.canvas;
    const s = (0.45 * Math.min(w, h) * this.scale) / (this.radius ?? 1);
    return [w / 2 + this.offset[0] + x1 * s, h / 2 + this.offset[1] - y2 * s, z2];
  }

  draw() {
    const { ctx, canvas } = this;
    ctx.fillStyle = '#ffffff';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    if (this.mesh) this.#drawMesh();
    if (this.points && (!this.mesh || this.pointsOverlay)) {
      // Over a mesh the points are orange, so the fit to them reads at a glance.
      ctx.fillStyle = this.mesh ? '#e0701a' : '#4a6fa5';
      for (let i = 0; i < this.points.length; i += 3) {
        const [x, y] = this.#project(this.points[i], this.points[i + 1], this.points[i + 2]);
        ctx.fillRect(x - 1, y - 1, 2, 2);
      }
    }
  }

  #drawMesh() {
    const { ctx } = this;
    const p = this.mesh.positions;
    const idx = this.mesh.indices;
    const screen = [];
    for (let i = 0; i < p.length; i += 3) screen.push(this.#project(p[i], p[i + 1], p[i + 2]));
    const tris = [];
    for (let t = 0; t < idx.length; t += 3) {
      const a = screen[idx[t]], b = screen[idx[t + 1]], c = screen[idx[t + 2]];
      // Shade by the view-space normal's facing (two-sided).
      const ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
      const vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
      const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
      const len = Math.hypot(nx, ny, nz) || 1;
      const light = 0.35 + 0.65 * Math.abs(nz / len);
      tris.push([(a[2] + b[2] + c[2]) / 3, a, b, c, light]);
    }
    tris.sort((s, t) => s[0] - t[0]);
    ctx.lineWidth = 1;
    ctx.strokeStyle = 'rgba(20, 30, 45, 0.8)';
    for (const [, a, b, c, light] of tris) {
      const g = Math.round(120 + 110 * light);
      ctx.fillStyle = `rgb(${Math.round(g * 0.55)}, ${Math.round(g * 0.75)}, ${g})`;
      ctx.beginPath();
      ctx.moveTo(a[0], a[1]);
      ctx.lineTo(b[0], b[1]);
      ctx.lineTo(c[0], c[1]);
      ctx.closePath();
      ctx.fill();
      ctx.stroke();
    }
  }
}
