// The worker of moved_spheres.js: a view-dependent request's split spheres, made once per step
// and kept, and per camera the splits whose screen error exceeds the tolerance, sent back by
// transfer.
import { ViewWorker } from './moved_spheres.js';

const state = new ViewWorker();
self.onmessage = ({ data }) => {
  const { answer, transfer } = state.answer(data);
  self.postMessage(answer, transfer);
};
