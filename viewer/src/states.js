// The model's states (time steps) as an engineer steps through them (docs/viewer.md "States"):
// first / previous / next / last buttons and keys (Home ← → End), a time slider that snaps to
// states unless "between states" is ticked, and playback at a chosen speed that loops, stops at
// the end (once) or runs back and forth (bounce). While playing, time moves smoothly between
// states; a pause lands on the nearest state unless interpolation was asked for.
const $ = (id) => document.getElementById(id);

export const PLAY_MODES = ['loop', 'once', 'bounce'];

// The next time and direction of playback after `dt` seconds: `t` in [0, last], `direction` ±1,
// `rate` in states per second. Returns {t, direction, ended} (ended: `once` reached the end).
export function advance(t, direction, rate, dt, last, mode) {
  if (last <= 0) return { t: 0, direction, ended: true };
  let next = t + direction * rate * dt;
  if (mode === 'bounce') {
    // Reflect at either end as often as a long frame needs.
    while (next > last || next < 0) {
      if (next > last) next = 2 * last - next, direction = -1;
      else next = -next, direction = 1;
    }
    return { t: next, direction, ended: false };
  }
  if (next >= last) return mode === 'once' ? { t: last, direction: 1, ended: true } : { t: next % last, direction: 1, ended: false };
  return { t: next, direction: 1, ended: false };
}

export class States {
  // viewer: {state, setTime(t), requestRender()}: the page's time (viewer.js).
  constructor(viewer) {
    this.viewer = viewer;
    this.ui = {
      section: $('states'),
      play: $('play'),
      time: $('time'),
      first: $('state-first'),
      prev: $('state-prev'),
      next: $('state-next'),
      last: $('state-last'),
      speed: $('play-speed'),
      mode: $('play-mode'),
      between: $('between-states'),
    };
    this.playing = false;
    this.direction = 1;
    this.lastFrame = 0;
    this.onEnd = null;  // called once when `once` playback reaches the last state
    const { ui } = this;
    ui.first.addEventListener('click', () => this.go(0));
    ui.prev.addEventListener('click', () => this.step(-1));
    ui.next.addEventListener('click', () => this.step(1));
    ui.last.addEventListener('click', () => this.go(Infinity));
    ui.play.addEventListener('click', () => this.toggle());
    ui.between.addEventListener('change', () => this.snapSlider());
    ui.time.addEventListener('input', () => this.scrubbed());
    window.addEventListener('keydown', (e) => this.key(e));
    this.snapSlider();
  }

  get stepCount() {
    return this.viewer.state.mesh?.head.stepCount ?? 1;
  }

  get speed() {
    return Number(this.ui.speed.value);
  }

  // States a second: the whole run in about 4 s at 1× (at least one state a second).
  get rate() {
    return Math.max(1, (this.stepCount - 1) / 4) * this.speed;
  }

  get mode() {
    return this.ui.mode.value;
  }

  // After HEAD: a one-state model has nothing to step through or to colour by displacement, so
  // no time controls at all and no displacement colours.
  onHead(head) {
    const still = head.stepCount < 2;
    this.ui.section.hidden = still;
    $('time-section').hidden = still;
    if (still) $('colour').querySelector('option[value="displacement"]')?.remove();
  }

  // The slider's step: whole states, or hundredths between them when asked for.
  snapSlider() {
    this.ui.time.step = this.ui.between.checked ? '0.01' : '1';
  }

  // The slider moved by hand (viewer.js sets the time from it): a pause, on a state unless
  // interpolation is asked for.
  scrubbed() {
    if (this.playing) this.pause();
  }

  // State i (clamped); fractional i interpolates. Stops playback.
  go(i) {
    if (!this.viewer.state.mesh?.hasBase) return;
    this.pause({ snap: false });
    this.viewer.setTime(Math.max(0, Math.min(i, this.stepCount - 1)));
  }

  // The next (+1) or previous (−1) whole state from where time is (from between two states, the
  // one on that side).
  step(d) {
    const t = this.viewer.state.t;
    this.go(d > 0 ? Math.floor(t + 1e-9) + 1 : Math.ceil(t - 1e-9) - 1);
  }

  toggle() {
    if (this.playing) this.pause();
    else this.play();
  }

  play({ speed, mode } = {}) {
    if (!this.viewer.state.nav || this.stepCount < 2) return;
    if (speed !== undefined) this.ui.speed.value = String(speed);
    if (mode !== undefined) {
      if (!PLAY_MODES.includes(mode)) throw new Error(`play mode '${mode}': one of ${PLAY_MODES.join(', ')}`);
      this.ui.mode.value = mode;
    }
    // `once` from the last state starts again from the first.
    if (this.mode === 'once' && this.viewer.state.t >= this.stepCount - 1) this.viewer.setTime(0);
    this.playing = true;
    this.lastFrame = 0;
    this.ui.play.textContent = '❚❚';
    this.viewer.requestRender();
  }

  pause({ snap = true } = {}) {
    if (!this.playing) return;
    this.playing = false;
    this.ui.play.textContent = '▶';
    if (snap && !this.ui.between.checked) this.viewer.setTime(Math.round(this.viewer.state.t));
    this.viewer.requestRender();
  }

  // Called by every frame (viewer.js): moves time while playing, by the time since the last frame.
  tick(now) {
    if (!this.playing || !this.viewer.state.mesh) return;
    const last = this.stepCount - 1;
    const rate = this.rate;
    const dt = this.lastFrame ? (now - this.lastFrame) / 1000 : 0;
    this.lastFrame = now;
    const r = advance(this.viewer.state.t, this.direction, rate, dt, last, this.mode);
    this.direction = r.direction;
    this.viewer.setTime(r.t);
    if (r.ended) {
      this.pause();
      this.onEnd?.();
    } else {
      this.viewer.requestRender();
    }
  }

  // ← → Home End step through states (also with the time slider focused, whose own arrow keys
  // would move by its step); space plays and pauses.
  key(e) {
    const target = e.target;
    if (target instanceof HTMLSelectElement || target instanceof HTMLTextAreaElement) return;
    // Another slider keeps its own arrow keys; a text or number field keeps every key.
    const other = target instanceof HTMLInputElement && target !== this.ui.time && target.type !== 'checkbox';
    if ((other && target.type !== 'range') || this.ui.section.hidden) return;
    const keys = { ' ': () => this.toggle() };
    if (!other) Object.assign(keys, { ArrowLeft: () => this.step(-1), ArrowRight: () => this.step(1), Home: () => this.go(0), End: () => this.go(Infinity) });
    const action = keys[e.key];
    if (!action) return;
    action();
    e.preventDefault();
  }
}
