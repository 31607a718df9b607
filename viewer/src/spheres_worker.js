// The worker of moved_spheres.js: the split spheres of a view-dependent request at a step,
// made off the page's main thread and sent back by transfer.
import { spheresAnswer } from './moved_spheres.js';

self.onmessage = ({ data }) => {
  const { answer, transfer } = spheresAnswer(data);
  self.postMessage(answer, transfer);
};
