// A heat map on a plain canvas (Chart.js 3 has none): one cell per pair of values, its colour
// the value on a colour-blind-safe scale (viridis) with a colour bar, its value and a symbol for
// its class written in it (never colour alone), outlines around the cells stable at an operating speed and marks
// on the edges between cells whose class changes. What it draws is kept on the canvas element
// (`canvas.heatmap`) so a test can compare it with the API's numbers.
import { onClear, plotFigure } from './charts.js';

// Viridis at five stops; linear in between.
const stops = [[0, [68, 1, 84]], [0.25, [59, 82, 139]], [0.5, [33, 145, 140]], [0.75, [94, 201, 98]], [1, [253, 231, 37]]];
function viridis(t) {
  t = Math.min(1, Math.max(0, t));
  for (let k = 1; k < stops.length; k++) {
    const [t1, c1] = stops[k];
    const [t0, c0] = stops[k - 1];
    if (t <= t1) return c0.map((c, i) => Math.round(c + ((c1[i] - c) * (t - t0)) / (t1 - t0)));
  }
  return stops[stops.length - 1][1];
}
const rgb = (c) => `rgb(${c[0]},${c[1]},${c[2]})`;
const dark = (c) => 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2] < 140;
const tick = (v) => (Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-2 && v !== 0) ? v.toExponential(2) : String(Number(v.toPrecision(4))));

const margin = { left: 96, right: 104, top: 12, bottom: 56 };

// rows/columns: { label, values }; cells: row-major, each null (not computed yet) or
// { value, symbol, text?, fill? } (text: what the cell says, its symbol where it does not fit;
// fill: a colour for cells without a value); stableAt(cell, speed):
// whether the cell is stable at that speed; edges: pairs of cell indices to mark.
export function drawHeatmap(container, { id, title, description, rows, columns, cells, valueLabel, stableAt, speed, edges = [] }) {
  const { canvas, frame } = plotFigure(container, { id, title, description, frameClass: 'plot-frame heatmap-frame', wide: true });
  const values = cells.map((c) => (c && c.value != null ? c.value : null));
  const finite = values.filter((v) => v !== null);
  const model = {
    rows: rows.values, columns: columns.values, values, axes: [rows.label, columns.label],
    symbols: cells.map((c) => (c ? c.symbol : null)),
    legend: { min: finite.length ? Math.min(...finite) : null, max: finite.length ? Math.max(...finite) : null, label: valueLabel },
    edges, speed, stable: [], texts: [],
    colorOf(v) {
      const { min, max } = model.legend;
      return viridis(max > min ? (v - min) / (max - min) : 0.5);
    },
    // The colour drawn inside cell (i, j), away from its symbol and edges: [r, g, b].
    pixel(i, j) {
      const r = model.rect(i, j);
      const ratio = canvas.width / model.width;
      const data = canvas.getContext('2d').getImageData(Math.round((r.x + Math.max(8, r.w * 0.15)) * ratio), Math.round((r.y + r.h / 2) * ratio), 1, 1).data;
      return [data[0], data[1], data[2]];
    },
    rect(i, j) {
      const w = (model.width - margin.left - margin.right) / columns.values.length;
      const h = (model.height - margin.top - margin.bottom) / rows.values.length;
      return { x: margin.left + j * w, y: margin.top + i * h, w, h };
    },
    setSpeed(v) { model.speed = v; draw(); },
  };
  canvas.heatmap = model;

  // Room for the rows: 36 px each, within what fits on a screen beside the controls.
  frame.style.height = `${Math.min(640, Math.max(260, rows.values.length * 36 + margin.top + margin.bottom))}px`;

  function draw() {
    const ratio = window.devicePixelRatio || 1;
    model.width = Math.max(320, frame.clientWidth);
    model.height = Math.max(200, frame.clientHeight);
    canvas.width = Math.round(model.width * ratio);
    canvas.height = Math.round(model.height * ratio);
    canvas.style.width = `${model.width}px`;
    canvas.style.height = `${model.height}px`;
    const ctx = canvas.getContext('2d');
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    ctx.clearRect(0, 0, model.width, model.height);
    ctx.font = '12px system-ui, sans-serif';
    const nr = rows.values.length;
    const nc = columns.values.length;
    const index = (i, j) => i * nc + j;
    model.stable = cells.map((c) => Boolean(c) && model.speed != null && stableAt(c, model.speed));

    // Cells: colour (or the class's own fill), symbol (as large as the cell allows).
    const { w: cellW, h: cellH } = model.rect(0, 0);
    const symbolSize = Math.floor(Math.min(14, cellW * 0.7, cellH * 0.7));
    model.texts = cells.map(() => null);
    for (let i = 0; i < nr; i++) {
      for (let j = 0; j < nc; j++) {
        const cell = cells[index(i, j)];
        const r = model.rect(i, j);
        const fill = !cell ? [255, 255, 255] : cell.value != null ? model.colorOf(cell.value) : cell.fill || [230, 230, 230];
        ctx.fillStyle = rgb(fill);
        ctx.fillRect(r.x, r.y, r.w, r.h);
        ctx.strokeStyle = '#ffffff';
        ctx.lineWidth = 1;
        ctx.strokeRect(r.x, r.y, r.w, r.h);
        if (!cell || symbolSize < 6) continue;
        ctx.fillStyle = dark(fill) ? '#ffffff' : '#000000';
        ctx.textAlign = 'center';
        ctx.textBaseline = 'middle';
        ctx.font = `bold ${symbolSize}px system-ui, sans-serif`;
        // The number and the symbol where they fit inside the cell (clear of where pixel() reads
        // its colour), else the symbol alone.
        const text = cell.text && ctx.measureText(cell.text).width <= r.w - 2 * Math.max(10, r.w * 0.15 + 2) ? cell.text : cell.symbol;
        model.texts[index(i, j)] = text;
        ctx.fillText(text, r.x + r.w / 2, r.y + r.h / 2);
        ctx.font = '12px system-ui, sans-serif';
      }
    }
    // Edges between two cells whose class changes: dashed red over a white halo.
    for (const [a, b] of edges) {
      const [ia, ja, ib, jb] = [Math.floor(a / nc), a % nc, Math.floor(b / nc), b % nc];
      const ra = model.rect(ia, ja);
      let segment;
      if (ia === ib) { const x = ra.x + (jb > ja ? ra.w : 0); segment = [x, ra.y + 3, x, ra.y + ra.h - 3]; }
      else { const y = ra.y + (ib > ia ? ra.h : 0); segment = [ra.x + 3, y, ra.x + ra.w - 3, y]; }
      for (const [style, width, dash] of [['#ffffff', 7, []], ['#d0021b', 4, [6, 4]]]) {
        ctx.strokeStyle = style; ctx.lineWidth = width; ctx.setLineDash(dash);
        ctx.beginPath(); ctx.moveTo(segment[0], segment[1]); ctx.lineTo(segment[2], segment[3]); ctx.stroke();
      }
      ctx.setLineDash([]);
    }
    // The stable window: the outline of the cells stable at the operating speed (black on white).
    for (const [style, width] of [['#ffffff', 5], ['#000000', 2.5]]) {
      ctx.strokeStyle = style; ctx.lineWidth = width;
      ctx.beginPath();
      for (let i = 0; i < nr; i++) {
        for (let j = 0; j < nc; j++) {
          if (!model.stable[index(i, j)]) continue;
          const r = model.rect(i, j);
          const open = (ii, jj) => ii < 0 || jj < 0 || ii >= nr || jj >= nc || !model.stable[index(ii, jj)];
          if (open(i - 1, j)) { ctx.moveTo(r.x, r.y); ctx.lineTo(r.x + r.w, r.y); }
          if (open(i + 1, j)) { ctx.moveTo(r.x, r.y + r.h); ctx.lineTo(r.x + r.w, r.y + r.h); }
          if (open(i, j - 1)) { ctx.moveTo(r.x, r.y); ctx.lineTo(r.x, r.y + r.h); }
          if (open(i, j + 1)) { ctx.moveTo(r.x + r.w, r.y); ctx.lineTo(r.x + r.w, r.y + r.h); }
        }
      }
      ctx.stroke();
    }
    // Axes: tick labels and titles with units.
    ctx.fillStyle = '#1b1f24';
    ctx.textBaseline = 'middle';
    ctx.textAlign = 'right';
    // Every k-th value only, where the labels would overlap.
    const rowStep = Math.ceil(16 / cellH);
    const columnStep = Math.ceil(56 / cellW);
    rows.values.forEach((v, i) => { if (i % rowStep) return; const r = model.rect(i, 0); ctx.fillText(tick(v), r.x - 6, r.y + r.h / 2); });
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    columns.values.forEach((v, j) => { if (j % columnStep) return; const r = model.rect(nr - 1, j); ctx.fillText(tick(v), r.x + r.w / 2, r.y + r.h + 4); });
    const plotBottom = model.height - margin.bottom;
    ctx.fillText(columns.label, margin.left + (model.width - margin.left - margin.right) / 2, plotBottom + 24);
    ctx.save();
    ctx.translate(14, margin.top + (plotBottom - margin.top) / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.fillText(rows.label, 0, 0);
    ctx.restore();
    // The colour bar: min at the bottom, max at the top.
    const barX = model.width - margin.right + 16;
    const gradient = ctx.createLinearGradient(0, plotBottom, 0, margin.top);
    stops.forEach(([t, c]) => gradient.addColorStop(t, rgb(c)));
    ctx.fillStyle = gradient;
    ctx.fillRect(barX, margin.top, 14, plotBottom - margin.top);
    ctx.fillStyle = '#1b1f24';
    ctx.textAlign = 'left';
    ctx.textBaseline = 'middle';
    if (model.legend.max !== null) {
      ctx.fillText(tick(model.legend.max), barX + 18, margin.top + 6);
      ctx.fillText(tick(model.legend.min), barX + 18, plotBottom - 6);
    }
    ctx.save();
    ctx.translate(model.width - 8, margin.top + (plotBottom - margin.top) / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textAlign = 'center';
    ctx.fillText(valueLabel, 0, 0);
    ctx.restore();
  }

  draw();
  const observer = new ResizeObserver(() => { if (frame.clientWidth !== model.width) draw(); });
  observer.observe(frame);
  onClear(() => observer.disconnect());
  return { canvas, frame, model, redraw: draw };
}
