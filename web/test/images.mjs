// Two pictures of the same size compared tile by tile: the mean absolute difference of the
// RGB levels (0-255) over each tile and over the whole picture.

export function compareImages(a, b, { tiles: [nx, ny] }) {
  if (a.width !== b.width || a.height !== b.height) {
    throw new Error(`sizes differ: ${a.width}x${a.height} against ${b.width}x${b.height}`);
  }
  const sums = new Float64Array(nx * ny);
  const counts = new Float64Array(nx * ny);
  let total = 0;
  for (let y = 0; y < a.height; y++) {
    const ty = Math.min(ny - 1, Math.floor((y * ny) / a.height));
    for (let x = 0; x < a.width; x++) {
      const tx = Math.min(nx - 1, Math.floor((x * nx) / a.width));
      const i = 4 * (y * a.width + x);
      const d = (Math.abs(a.data[i] - b.data[i]) + Math.abs(a.data[i + 1] - b.data[i + 1]) +
        Math.abs(a.data[i + 2] - b.data[i + 2])) / 3;
      sums[ty * nx + tx] += d;
      counts[ty * nx + tx] += 1;
      total += d;
    }
  }
  const means = Array.from(sums, (s, k) => s / counts[k]);
  const worstIndex = means.indexOf(Math.max(...means));
  return {
    means,
    worst: { tile: [worstIndex % nx, Math.floor(worstIndex / nx)], meanAbs: means[worstIndex] },
    summary: {
      meanAbs: +(total / (a.width * a.height)).toFixed(3),
      worstTileMeanAbs: +means[worstIndex].toFixed(3),
    },
  };
}
