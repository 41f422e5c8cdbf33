// Mouse, touch and keyboard on the viewer's canvas, turned into camera operations on `target`
// (the 2D viewer, or the proxy of the wgpu viewer in the worker):
//   orbit(dx, dy) radians, pan(dx, dy) canvas pixels, zoom(factor > 1 = closer), fit().
// Drag orbits; shift-drag or right-drag pans; the wheel and a two-finger pinch zoom; arrow
// keys orbit, + and - zoom, F fits.
export function bindControls(canvas, target) {
  canvas.tabIndex = 0;
  const pointers = new Map();
  let last = null;
  // Client pixels to the canvas's own pixels (CSS scales the canvas).
  const scale = () => canvas.width / Math.max(1, canvas.getBoundingClientRect().width);
  canvas.addEventListener('pointerdown', (e) => {
    canvas.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, [e.clientX, e.clientY]);
    last = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!pointers.has(e.pointerId)) return;
    const prev = pointers.get(e.pointerId);
    pointers.set(e.pointerId, [e.clientX, e.clientY]);
    if (pointers.size === 2) {
      const other = [...pointers.entries()].find(([id]) => id !== e.pointerId)[1];
      const before = Math.hypot(prev[0] - other[0], prev[1] - other[1]);
      const after = Math.hypot(e.clientX - other[0], e.clientY - other[1]);
      if (before > 0 && after > 0) target.zoom(after / before);
    } else if (last) {
      const dx = e.clientX - last.x;
      const dy = e.clientY - last.y;
      if (last.pan) target.pan(dx * scale(), dy * scale());
      else target.orbit(dx * 0.01, dy * 0.01);
      last.x = e.clientX;
      last.y = e.clientY;
    }
  });
  const end = (e) => {
    pointers.delete(e.pointerId);
    if (pointers.size === 0) last = null;
  };
  canvas.addEventListener('pointerup', end);
  canvas.addEventListener('pointercancel', end);
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    target.zoom(Math.exp(-e.deltaY * 0.001));
  }, { passive: false });
  canvas.addEventListener('keydown', (e) => {
    const step = 0.1;
    if (e.key === 'ArrowLeft') target.orbit(-step, 0);
    else if (e.key === 'ArrowRight') target.orbit(step, 0);
    else if (e.key === 'ArrowUp') target.orbit(0, -step);
    else if (e.key === 'ArrowDown') target.orbit(0, step);
    else if (e.key === '+' || e.key === '=') target.zoom(1.1);
    else if (e.key === '-') target.zoom(1 / 1.1);
    else if (e.key === 'f' || e.key === 'F') target.fit();
    else return;
    e.preventDefault();
  });
}
