// Pictures of the view (docs/viewer.md "Images"): a PNG of the canvas as it is (with the axis
// triad), and the animation from the first state to the last recorded as WebM with the
// browser's MediaRecorder from the canvas's own stream. Both are saved as downloads named after
// the model.
const $ = (id) => document.getElementById(id);

export const WEBM = 'video/webm';
const FPS = 30;
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, Math.max(0, ms)));

// Saves `href` (a data: or blob: URL) as a download named `name` (also the history's CSV).
export function download(href, name) {
  const a = document.createElement('a');
  a.href = href;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
}

export class Images {
  // viewer: {state, canvas, renderNow(): draws the frame at once, states (states.js)}.
  constructor(viewer) {
    this.viewer = viewer;
    this.ui = { png: $('save-png'), record: $('record-webm'), status: $('images-status') };
    this.recording = null;  // {recorder, done: Promise<Blob>}
    this.ui.png.addEventListener('click', () => download(this.screenshot(), `${this.baseName()}.png`));
    this.ui.record.addEventListener('click', () => (this.recording ? this.stop() : this.saveRecording()));
  }

  // The model's name without .dpm, and the state shown: rail-step12.
  baseName() {
    const { name, t } = this.viewer.state;
    const step = Math.round(t * 100) / 100;
    return `${name.replace(/\.dpm$/i, '') || 'model'}-step${step}`;
  }

  // The view as a PNG data URL: drawn and read in one task, so the canvas needs no preserved
  // drawing buffer.
  screenshot() {
    this.exporting(true);
    this.viewer.renderNow();
    const url = this.viewer.canvas.toDataURL('image/png');
    this.exporting(false);
    return url;
  }

  // A saved picture or video has no panel over it: the model at its centre, not moved aside
  // for the panel as on the page (viewer.js dodgePanel()).
  exporting(on) {
    this.viewer.state.exporting = on;
    this.viewer.dodgePanel();
  }

  // Records the animation once through, first state to last at the chosen speed (the rest of
  // the page as it is), and resolves with the WebM Blob. Frame by frame: each frame is time
  // 1/FPS further and sent to the stream when drawn, so that every state is in the video even
  // when the machine draws slower than FPS (the video then runs slower). The first and last
  // states are held for half a second; a one-state model records its still picture.
  record() {
    if (this.recording) return Promise.reject(new Error('already recording'));
    if (typeof MediaRecorder === 'undefined' || !MediaRecorder.isTypeSupported(WEBM))
      return Promise.reject(new Error('this browser cannot record WebM (MediaRecorder)'));
    const { states } = this.viewer;
    states.pause();
    // One stream for every recording, a frame when asked for: Chrome sends no frames on a
    // second capture stream of a canvas whose first one was stopped.
    this.stream ??= this.viewer.canvas.captureStream(0);
    const stream = this.stream;
    const [track] = stream.getVideoTracks();
    const recorder = new MediaRecorder(stream, { mimeType: WEBM });
    const chunks = [];
    let started;
    const firstData = new Promise((resolve) => (started = resolve));
    recorder.addEventListener('dataavailable', (e) => {
      if (e.data.size) chunks.push(e.data), started();
    });
    const done = new Promise((resolve, reject) => {
      recorder.addEventListener('stop', () => {
        this.recording = null;
        this.exporting(false);
        this.ui.record.textContent = '● Record WebM';
        this.ui.status.textContent = '';
        resolve(new Blob(chunks, { type: WEBM }));
      });
      recorder.addEventListener('error', (e) => (this.exporting(false), reject(e.error ?? new Error('recording failed'))));
    });
    this.recording = { recorder, stopped: false };
    this.exporting(true);
    this.ui.record.textContent = '■ Stop';
    this.ui.status.textContent = 'recording…';
    recorder.start(200);
    this.frames(track).then(async () => {
      // An encoder that starts slowly (a busy machine) has sent nothing yet: stopping now would
      // give an empty file.
      await Promise.race([firstData, sleep(5000)]);
      recorder.stop();
    });
    return done;
  }

  // Draws and sends the frames: the first state held, the run, the last state held.
  async frames(track) {
    const { states } = this.viewer;
    const last = states.stepCount - 1;
    const hold = FPS / 2;
    const run = last > 0 ? Math.ceil((last / states.rate) * FPS) : 0;
    for (let k = -hold; k <= run + hold && !this.recording.stopped; k++) {
      const start = performance.now();
      if (last > 0) this.viewer.setTime(Math.min(last, Math.max(0, (k * states.rate) / FPS)));
      this.viewer.renderNow();
      track.requestFrame();
      await sleep(1000 / FPS - (performance.now() - start));
    }
  }

  // The Stop button while recording: the video ends at the state shown.
  stop() {
    if (this.recording) this.recording.stopped = true;
  }

  async saveRecording() {
    const name = `${this.viewer.state.name.replace(/\.dpm$/i, '') || 'model'}.webm`;
    try {
      const blob = await this.record();
      const url = URL.createObjectURL(blob);
      download(url, name);
      setTimeout(() => URL.revokeObjectURL(url), 10000);
    } catch (e) {
      this.ui.status.textContent = String(e.message ?? e);
    }
  }
}
