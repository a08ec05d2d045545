// Plots with Chart.js (the global `Chart` of the embedded UMD build). Each plot is a <figure>
// with a caption and a labelled canvas; the data drawn is exactly the API's numbers, so the
// browser test reads it back with Chart.getChart(canvas).data.

const palette = ['#1f5fa8', '#c0392b', '#2e8b57', '#8e44ad', '#d35400', '#16a085', '#7f8c8d', '#b7950b'];
export const color = (i) => palette[i % palette.length];

const charts = [];

export function clearPlots(container) {
  while (charts.length) charts.pop().destroy();
  container.replaceChildren();
}

// `points(xs, ys)`: Chart.js {x, y} pairs, nulls (non-finite values) kept as gaps.
export const points = (xs, ys) => xs.map((x, i) => ({ x, y: ys[i] }));

export function addPlot(container, { id, title, description, type = 'line', data, x, y, y2, stacked = false }) {
  const figure = document.createElement('figure');
  figure.className = 'plot';
  const canvas = document.createElement('canvas');
  canvas.id = `plot-${id}`;
  canvas.setAttribute('role', 'img');
  canvas.setAttribute('aria-label', `${title}. ${description || ''}`);
  const caption = document.createElement('figcaption');
  caption.textContent = title;
  const frame = document.createElement('div');
  frame.className = 'plot-frame';
  frame.append(canvas);
  figure.append(caption, frame);
  container.append(figure);
  const scales = {
    x: { type: type === 'bar' ? 'category' : 'linear', title: { display: Boolean(x), text: x }, stacked },
    y: { title: { display: Boolean(y), text: y }, stacked },
  };
  if (y2) scales.y2 = { position: 'right', title: { display: true, text: y2 }, grid: { drawOnChartArea: false } };
  const chart = new Chart(canvas, {
    type,
    data,
    options: {
      animation: false,
      responsive: true,
      maintainAspectRatio: false,
      parsing: type === 'bar' ? undefined : false,
      normalized: true,
      spanGaps: false,
      interaction: { mode: 'nearest', intersect: false },
      elements: { point: { radius: 0, hitRadius: 6 } },
      plugins: { legend: { labels: { boxWidth: 14 } } },
      scales,
    },
  });
  charts.push(chart);
  return chart;
}

// A vertical marker line at `x` from `low` to `high` on the y axis `axis`.
export const marker = (label, x, low, high, colour, axis = 'y') => ({
  label, data: [{ x, y: low }, { x, y: high }], borderColor: colour, backgroundColor: colour,
  borderDash: [6, 4], borderWidth: 2, pointRadius: [0, 4], yAxisID: axis,
});

export const line = (label, data, i, extra = {}) => ({
  label, data, borderColor: color(i), backgroundColor: color(i), borderWidth: 2, ...extra,
});
