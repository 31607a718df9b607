// A click on the canvas, as the picture's own controls take it (the axis triad in
// orientation.js, picking in inspect.js): the left button pressed and released within a few
// pixels — a longer move is a drag, which orbits the view (OrbitControls) and picks nothing.
const CLICK_SLOP = 4;  // CSS pixels a click may move and still be a click

// Calls handler(x, y, event) with the CSS pixel of the canvas (from its top left) on each click.
export function onCanvasClick(canvas, handler) {
  let down = null;
  canvas.addEventListener('pointerdown', (e) => (down = { x: e.clientX, y: e.clientY, button: e.button }));
  canvas.addEventListener('pointerup', (e) => {
    if (!down || down.button !== 0 || Math.hypot(e.clientX - down.x, e.clientY - down.y) > CLICK_SLOP) return;
    const r = canvas.getBoundingClientRect();
    handler(e.clientX - r.left, e.clientY - r.top, e);
  });
}
