// The hexagonal tiling texture for the textured result, drawn on a canvas.
//
// Convention of the textured mesh: texture coordinates (u, v) ∈ [0,1]² cover one rectangular
// period of the Eisenstein lattice with unit edge length, which is 1 wide and √3 high. In lattice
// units that period holds the lattice points (0,0), (1,0), (0,√3), (1,√3) and (½, √3/2); the
// hexagon of the dual tiling around each lattice point has circumradius 1/√3, with two vertices
// straight above and below it (its edges cross the lattice edges at right angles). Rows of hexagons
// alternate in colour so that the tiling's orientation stays visible.

const kSqrt3 = Math.sqrt(3);

/** Draws one period; `width` in pixels, the height is width·√3 (rounded). */
export function drawHexTile(canvas, width = 256) {
  const height = Math.round(width * kSqrt3);
  canvas.width = width;
  canvas.height = height;
  const ctx = canvas.getContext('2d');
  const scale = width; // pixels per lattice unit; v grows upwards, canvas y downwards
  const toCanvas = (x, y) => [x * scale, height - y * scale];
  const radius = 1 / kSqrt3;
  const rowColours = ['#f2b134', '#3e8ed0'];

  ctx.fillStyle = rowColours[0];
  ctx.fillRect(0, 0, width, height);
  // Lattice points of this period and of its neighbours, so that hexagons cut by the border
  // are drawn in full and the tile repeats without seams.
  for (let j = -1; j <= 3; ++j) {
    for (let i = -1; i <= 2; ++i) {
      const cx = i + (j % 2 !== 0 ? 0.5 : 0);
      const cy = (j * kSqrt3) / 2;
      ctx.beginPath();
      for (let k = 0; k < 6; ++k) {
        const angle = Math.PI / 2 + (k * Math.PI) / 3;
        const [x, y] = toCanvas(cx + radius * Math.cos(angle), cy + radius * Math.sin(angle));
        if (k === 0) ctx.moveTo(x, y);
        else ctx.lineTo(x, y);
      }
      ctx.closePath();
      ctx.fillStyle = rowColours[((j % 2) + 2) % 2];
      ctx.fill();
      ctx.lineWidth = Math.max(2, width / 64);
      ctx.strokeStyle = '#1d2a3a';
      ctx.stroke();
    }
  }
  return canvas;
}
