// The benchmarks' time scrub (viewer.js's dpmViewer.scrub(), bench/scrub.mjs): a new fractional
// step every animation frame for `frames` frames, as a dragged time slider gives; resolves with
// the frame times in ms and the JS time spent in updates per frame.
// page: {state, ui, renderer, scene, camera, updateTime(options)} (viewer.js).
export function scrub({ state, ui, renderer, scene, camera, updateTime }, frames = 120) {
  return new Promise((resolve) => {
    const stamps = [];
    let update = 0;
    const m = state.mesh.head.stepCount;
    const tick = (now) => {
      stamps.push(now);
      if (stamps.length > frames) {
        const gaps = stamps.slice(1).map((s, i) => s - stamps[i]);
        resolve({ frameMs: gaps, updateMs: update / frames });
        return;
      }
      const start = performance.now();
      state.t = (stamps.length * 0.37) % (m - 1);
      ui.time.value = String(state.t);
      updateTime({ render: false });
      update += performance.now() - start;
      renderer.render(scene, camera);
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
}
