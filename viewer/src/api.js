// window.dynpm, the page's scripting API (docs/viewer.md "Scripting API"), used by the browser
// tests and by anyone driving the page (a console, a headless browser making pictures). Every
// part of the page adds its functions with Object.assign(window.dynpm ??= {}, {…}); this one
// adds `ready` and the view's: states, level, camera, deformation, images.
import { Navigator } from './dpm.js';

// viewer: {state, loading (load()'s promise), setVertexCount(n, now), states, orientation,
// deformation, images} (viewer.js).
export function installApi(viewer) {
  const { state, states, orientation, deformation, images } = viewer;
  const navigator = () => {
    if (!(state.nav instanceof Navigator) && !state.nav?.selective) throw new Error('the model is not loaded yet: await dynpm.ready');
    return state.nav;
  };
  const number = (what, x) => {
    if (typeof x !== 'number' || !Number.isFinite(x)) throw new TypeError(`${what}: a finite number, not ${x}`);
    return x;
  };

  // Resolves once the file is read and the level shown is the finest loaded (the Navigator made
  // and every level step done); rejects with the page's error.
  const ready = viewer.loading.then(
    () =>
      new Promise((resolve) => {
        const settled = () => state.nav instanceof Navigator && !state.levelPending && state.nav.vertexCount === state.mesh.vertexCountLoaded;
        const wait = () => (settled() ? resolve(window.dynpm) : requestAnimationFrame(wait));
        wait();
      }),
  );
  ready.catch(() => {});  // the page shows the error; a script awaiting ready gets it too

  Object.assign((window.dynpm ??= {}), {
    ready,

    // State i, 0-based; a fractional i interpolates between the states around it. Pauses.
    setStep(i) {
      navigator();
      const last = state.mesh.head.stepCount - 1;
      if (number('step', i) < 0 || i > last) throw new RangeError(`step ${i}: from 0 to ${last}`);
      states.go(i);
      return state.t;
    },

    // The level by {vertices: n}, {ratio: r} (r of the full mesh's vertices, 0 … 1; at least the
    // base mesh) or {error: e} (the coarsest level whose error is ≤ e, in the model's length
    // unit). Returns what is shown: {vertices, error}.
    setLevel(spec = {}) {
      const nav = navigator();
      const h = state.mesh.head;
      let n;
      if ('vertices' in spec) n = Math.round(number('vertices', spec.vertices));
      else if ('ratio' in spec) {
        if (number('ratio', spec.ratio) < 0 || spec.ratio > 1) throw new RangeError(`ratio ${spec.ratio}: from 0 to 1`);
        n = Math.round(spec.ratio * h.vertexCount);
      } else if ('error' in spec) {
        if (number('error', spec.error) < 0) throw new RangeError(`error ${spec.error}: ≥ 0`);
        n = state.mesh.vertexCountForError(spec.error);
      } else throw new TypeError('setLevel: {vertices}, {ratio} or {error}');
      viewer.setVertexCount(Math.max(h.baseVertexCount, Math.min(n, h.vertexCount)), true);
      return { vertices: nav.activeVertexCount ?? nav.vertexCount, error: nav.error };  // refined: the level elsewhere
    },

    // '+x', '-x', '+y', '-y', '+z', '-z' (the direction looked along), 'iso' or 'fit'.
    setView(name) {
      orientation.setView(name);
    },
    // 'y' or 'z'; then the isometric view.
    setUp(axis) {
      orientation.setUp(axis);
    },

    // The deformation scale, 0 (undeformed) … 10, and the undeformed ghost.
    setDeformationScale(s) {
      deformation.setScale(number('scale', s));
    },
    setGhost(on) {
      deformation.setGhost(on);
    },

    // Playback: {speed (× the 4-second run), mode: 'loop' | 'once' | 'bounce'}.
    play(options = {}) {
      navigator();
      states.play(options);
    },
    pause() {
      states.pause();
    },

    // The view as a PNG data URL; the animation (first to last state) as a WebM Blob.
    screenshot() {
      navigator();
      return images.screenshot();
    },
    record() {
      navigator();
      return images.record();
    },

    // What the view shows, for scripts and tests.
    view() {
      return {
        step: state.t,
        stepCount: state.mesh?.head.stepCount ?? 0,
        playing: states.playing,
        speed: states.speed,
        mode: states.mode,
        scale: deformation.scale,
        ghost: deformation.ghost.visible,
        vertices: state.nav?.vertexCount ?? 0,
        error: state.nav?.error ?? null,
        ...orientation.describe(),
      };
    },
  });
}
