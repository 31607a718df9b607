// The picture as a small grey-level image, for the browser tests (viewer.js's
// dpmViewer.snapshot()): rendered and read back at once, so no preserveDrawingBuffer is needed.
export function greySnapshot(renderer, scene, camera, size = 64) {
  const { width: w, height: h, rgba } = pixels(renderer, scene, camera);
  const grey = new Float32Array(size * size);
  const count = new Float32Array(size * size);
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) {
      const i = 4 * (y * w + x);
      const cell = Math.floor((y * size) / h) * size + Math.floor((x * size) / w);
      grey[cell] += 0.299 * rgba[i] + 0.587 * rgba[i + 1] + 0.114 * rgba[i + 2];
      count[cell]++;
    }
  for (let i = 0; i < grey.length; i++) grey[i] /= count[i] || 1;
  return Array.from(grey);
}

// The picture at full size: {width, height, rgba} (rows bottom-up, as WebGL reads them).
export function pixels(renderer, scene, camera) {
  renderer.render(scene, camera);
  const gl = renderer.getContext();
  const width = gl.drawingBufferWidth, height = gl.drawingBufferHeight;
  const rgba = new Uint8Array(4 * width * height);
  gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
  return { width, height, rgba };
}
