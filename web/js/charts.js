// Plots with Chart.js (the global `Chart` of the embedded UMD build). Each plot is a <figure>
// with a caption and a labelled canvas; the data drawn is exactly the API's numbers, so the
// browser test reads it back with Chart.getChart(canvas).data.

const palette = ['#1f5fa8', '#c0392b', '#2e8b57', '#8e44ad', '#d35400', '#16a085', '#7f8c8d', '#b7950b'];
export const color = (i) => palette[i % palette.length];

const charts = [];
const cleanups = [];

// ---- units as shown --------------------------------------------------------------------------
// A unit as the service writes it (UCUM code, x-unit: "Pa.s", "um", "kN.m", "/s") as a label prints it.
export function unitText(code) {
  if (!code || code === '1') return '';
  return code.replace(/(^|[./])um\b/g, '$1µm').replace(/m2\b/g, 'm²').replace(/m3\b/g, 'm³')
    .replace(/\./g, '·').replace(/^\//, '1/');
}
// SI (the API's units) or plant units: the JSON is always SI; in plant units the page shows
// speeds in m/min and viscosities in mPa·s (axes, tables, headline), converting what it shows,
// and asks the service for CSV with ?units=plant (docs/http-api.md, "Plant units").
const plantUnits = { 'm/s': ['m/min', 60], 'Pa·s': ['mPa·s', 1000] };
let unitMode = 'si';
export const unitsShown = () => unitMode;
export function setUnitsShown(mode) { unitMode = mode === 'plant' ? 'plant' : 'si'; }
// How a value in `unit` (as printed) is shown: { unit, factor }.
export function shown(unit) {
  const plant = unitMode === 'plant' && plantUnits[unitText(unit) || unit];
  return plant ? { unit: plant[0], factor: plant[1] } : { unit, factor: 1 };
}
// A number in `unit` as shown (null and text unchanged).
export const inShown = (value, unit) => (typeof value === 'number' ? value * shown(unit).factor : value);
// Every "[unit]" of a label in the units shown: 'rolling speed [m/s]' → 'rolling speed [m/min]'.
export const labelShown = (text) => (typeof text === 'string' ? text.replace(/\[([^\]]+)\]/g, (_, u) => `[${shown(u).unit}]`) : text);
// The factor of the unit a label ends with ('critical speed [m/s]': 60 in plant units).
export function factorOf(text) {
  const unit = /\[([^\]]+)\]\s*$/.exec(typeof text === 'string' ? text : '');
  return unit ? shown(unit[1]).factor : 1;
}
const scaled = (v, f) => (f === 1 || typeof v !== 'number' ? v : v * f);
// A chart's datasets in the units its axis titles show (the titles say the API's units).
function datasetsShown(datasets, factors) {
  return datasets.map((d) => {
    const fx = factors.x || 1;
    const fy = factors[d.yAxisID || 'y'] || 1;
    const data = fx === 1 && fy === 1 ? d.data : d.data.map((p) => (p && typeof p === 'object'
      ? { ...p, x: scaled(p.x, fx), y: scaled(p.y, fy), ...(p.yError !== undefined ? { yError: scaled(p.yError, fy) } : {}) }
      : scaled(p, fy)));
    return { ...d, label: labelShown(d.label), data };
  });
}
// New datasets for a chart made by addPlot (a running job's points), in the units it shows.
export function setDatasets(chart, datasets) {
  chart.data.datasets = datasetsShown(datasets, chart.$factors || {});
  chart.update('none');
}

export function clearPlots(container) {
  while (charts.length) charts.pop().destroy();
  while (cleanups.length) cleanups.pop()();
  container.replaceChildren();
}
// Something to undo when the plots are cleared (a resize observer of the heat map).
export const onClear = (undo) => cleanups.push(undo);

// `points(xs, ys)`: Chart.js {x, y} pairs, nulls (non-finite values) kept as gaps.
export const points = (xs, ys) => xs.map((x, i) => ({ x, y: ys[i] }));

// A figure with a caption and a frame holding a labelled canvas (Chart.js or the heat map draws into it).
export function plotFigure(container, { id, title, description, frameClass = 'plot-frame', wide = false }) {
  const figure = document.createElement('figure');
  figure.className = wide ? 'plot wide' : 'plot';
  const canvas = document.createElement('canvas');
  canvas.id = `plot-${id}`;
  canvas.setAttribute('role', 'img');
  canvas.setAttribute('aria-label', `${title}. ${description || ''}`);
  const caption = document.createElement('figcaption');
  caption.textContent = title;
  const frame = document.createElement('div');
  frame.className = frameClass;
  frame.append(canvas);
  figure.append(caption, frame);
  container.append(figure);
  return { figure, canvas, frame };
}

// Vertical error bars for datasets with `errorBars: true` whose points carry `yError` (one
// standard uncertainty): drawn after the datasets, and the y axis widened to hold them.
// Chart.js 3 has no error bars of its own; this is the page's own small plugin.
export const errorBars = {
  id: 'rollgapErrorBars',
  afterDataLimits(chart, { scale }) {
    if (scale.axis !== 'y') return;
    for (const dataset of chart.data.datasets) {
      if (!dataset.errorBars || (dataset.yAxisID || 'y') !== scale.id) continue;
      for (const p of dataset.data) {
        if (p.y == null || p.yError == null) continue;
        scale.min = Math.min(scale.min, p.y - p.yError);
        scale.max = Math.max(scale.max, p.y + p.yError);
      }
    }
  },
  afterDatasetsDraw(chart) {
    const { ctx } = chart;
    chart.data.datasets.forEach((dataset, i) => {
      if (!dataset.errorBars || !chart.isDatasetVisible(i)) return;
      const xScale = chart.scales[dataset.xAxisID || 'x'];
      const yScale = chart.scales[dataset.yAxisID || 'y'];
      ctx.save();
      ctx.strokeStyle = dataset.borderColor;
      ctx.lineWidth = 1.5;
      for (const p of dataset.data) {
        if (p.y == null || p.yError == null) continue;
        const x = xScale.getPixelForValue(p.x);
        const top = yScale.getPixelForValue(p.y + p.yError);
        const bottom = yScale.getPixelForValue(p.y - p.yError);
        ctx.beginPath();
        ctx.moveTo(x, top); ctx.lineTo(x, bottom);
        ctx.moveTo(x - 5, top); ctx.lineTo(x + 5, top);
        ctx.moveTo(x - 5, bottom); ctx.lineTo(x + 5, bottom);
        ctx.stroke();
      }
      ctx.restore();
    });
  },
};

// `yScale`: more options of the y axis (min, max, the ticks of lanes drawn on a linear axis);
// `wide`: the full width of the plots grid.
// Axis titles end with the API's unit ("[m/s]"): in plant units the data on that axis is
// converted and the title says the unit shown.
export function addPlot(container, { id, title, description, type = 'line', data, x, y, y2, stacked = false, plugins = [], xTicks, yTicks, yScale, small = false, pointLegend = false, wide = false }) {
  const factors = { x: type === 'bar' ? 1 : factorOf(x), y: factorOf(y), y2: factorOf(y2) };
  [title, description, x, y, y2] = [title, description, x, y, y2].map(labelShown);
  data = { ...data, datasets: datasetsShown(data.datasets, factors) };
  const { canvas } = plotFigure(container, { id, title, description, frameClass: small ? 'plot-frame small' : 'plot-frame', wide });
  const scales = {
    x: { type: type === 'bar' ? 'category' : 'linear', title: { display: Boolean(x), text: x }, stacked, ...(xTicks ? { ticks: xTicks } : {}) },
    y: { title: { display: Boolean(y), text: y }, stacked, ...(yTicks ? { ticks: yTicks } : {}), ...(yScale || {}) },
  };
  if (y2) scales.y2 = { position: 'right', title: { display: true, text: y2 }, grid: { drawOnChartArea: false } };
  const chart = new Chart(canvas, {
    type,
    data,
    plugins,
    options: {
      animation: false,
      responsive: true,
      maintainAspectRatio: false,
      parsing: type === 'bar' ? undefined : false,
      normalized: true,
      spanGaps: false,
      interaction: { mode: 'nearest', intersect: false },
      elements: { point: { radius: 0, hitRadius: 6 } },
      plugins: { legend: { labels: {
        boxWidth: 14, usePointStyle: pointLegend,
        // One entry per label (several markers may share one, e.g. the chatter type changes).
        filter: (item, chartData) => chartData.datasets.findIndex((d) => d.label === item.text) === item.datasetIndex,
      } } },
      scales,
    },
  });
  chart.$factors = factors;
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
