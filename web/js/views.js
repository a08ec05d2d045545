// What each analysis draws and lists, keyed by the analysis' name. Which analyses the page
// offers, their labels, routes and whether they have CSV come from the OpenAPI document
// (x-rollgap-analyses, the service's analysis table); an analysis offered without a view here
// gets `plainView`. Every view takes the service's answer as it is (the numbers are plotted
// unchanged) and returns its headline rows. `job`: the page runs it as a job; `partial`: a
// running job's finished points as a result to draw.
import { call, getJson } from './api.js';
import { addPlot, color, errorBars, factorOf, inShown, labelShown, line, marker, onClear, points, setDatasets, shown, unitText } from './charts.js';
import { fieldInfo, fieldLabel, quantityLabel, unitOf } from './editor.js';
import { drawHeatmap } from './heatmap.js';
import { table } from './report.js';

const fmt = (value, digits = 4) => {
  if (value === null || value === undefined) return '—';
  if (typeof value !== 'number') return String(value);
  return Math.abs(value) >= 1e5 || (Math.abs(value) < 1e-3 && value !== 0) ? value.toExponential(3) : Number(value.toPrecision(digits)).toString();
};
// A headline row: the value in the units shown (plant units: m/min, mPa·s) and that unit.
const row = (label, value, unit = '') => [label, fmt(inShown(value, unit)), shown(unit).unit];
// A speed in the units shown, with its unit: "15 m/s" or "900 m/min".
const speedText = (value, digits) => `${fmt(inShown(value, 'm/s'), digits)} ${shown('m/s').unit}`;
const max = (values) => Math.max(...values.filter((v) => v !== null));
const min = (values) => Math.min(...values.filter((v) => v !== null));

// Chatter types (docs/model.md, "Chatter type"): a name and a symbol each, so a plot never
// tells them apart by colour alone; a map cell's symbol is the shape a sweep's points have.
const chatterTypes = {
  third_octave: { name: 'third-octave', symbol: '●', pointStyle: 'circle' },
  fifth_octave: { name: 'fifth-octave', symbol: '▲', pointStyle: 'triangle' },
  other: { name: 'other', symbol: '■', pointStyle: 'rect' },
};
const chatterName = (type) => (type ? (chatterTypes[type] || { name: type }).name : '—');

// The values of a sweep's or map axis' options (values, or from + (to − from)·i/(count − 1)).
export function optionValues(axis) {
  if (!axis) return [];
  if (Array.isArray(axis.values)) return axis.values;
  const { from, to, count } = axis.range || {};
  if (!(count >= 2)) return [];
  return Array.from({ length: count }, (_, i) => from + ((to - from) * i) / (count - 1));
}
// Index of the entry of `list` nearest `value` (the changes' values are rounded to 12 digits).
const nearest = (list, value) => list.reduce((best, v, i) => (Math.abs(v - value) < Math.abs(list[best] - value) ? i : best), 0);
// A swept field as an axis names it: its title and unit from the document ("Lubricant
// viscosity [Pa·s]"), else its pointer and the unit the answer gives.
const axisLabel = (doc, pointer, unit) => {
  if (doc && fieldInfo(doc, pointer).title !== pointer) return fieldLabel(doc, pointer);
  const u = (doc && unitOf(doc, pointer)) || (unit && unit !== '1' ? unit : '');
  return u ? `${pointer} [${u}]` : pointer;
};
const fieldName = (doc, pointer) => (doc ? fieldInfo(doc, pointer).title : pointer);
// A number of the tandem document as a label names it: its title and the stand or span it
// belongs to ("Lubricant viscosity of stand 3", "Interstand tension between stands 2 and 3"),
// and its unit; its pointer when the document has no title for it.
function millField(doc, pointer) {
  const { title, unit } = doc ? fieldInfo(doc, pointer, 'Tandem') : { title: pointer, unit: '' };
  if (title === pointer) return { name: pointer, unit };
  const stand = /^\/stands\/(\d+)\//.exec(pointer) || /^\/exit_thickness_mm\/(\d+)$/.exec(pointer);
  const span = /^\/spans\/[^/]+\/(\d+)$/.exec(pointer);
  const where = stand ? ` of stand ${Number(stand[1]) + 1}` : span ? ` between stands ${Number(span[1]) + 1} and ${Number(span[1]) + 2}` : '';
  return { name: `${title}${where}`, unit };
}

// A figure holding tables or controls rather than a plot (full width of the plots grid).
function panel(plots, title) {
  const figure = document.createElement('figure');
  figure.className = 'plot wide';
  const caption = document.createElement('figcaption');
  caption.textContent = title;
  figure.append(caption);
  plots.append(figure);
  return figure;
}
// A table whose numeric cells keep the exact number in data-value (what a test compares); a
// column whose header ends with a unit ("[m/s]") in the units shown.
function numberTable(caption, header, rows) {
  const factors = header.map(factorOf);
  rows = rows.map((r) => r.map((cell, j) => (typeof cell === 'number' && factors[j] !== 1 ? cell * factors[j] : cell)));
  header = header.map(labelShown);
  const t = table(caption, rows.map((r) => r.map((cell) => (typeof cell === 'number' ? fmt(cell) : cell ?? '—'))), header);
  [...t.tBodies[0].rows].forEach((tr, i) => rows[i].forEach((cell, j) => { if (typeof cell === 'number') tr.cells[j].dataset.value = String(cell); }));
  return t;
}

function drawBite(plots, result, rollSpeed, prefix = '') {
  const d = result.distribution;
  if (!d) return;
  const x = d.x_mm;
  const peak = max(d.pressure_MPa);
  const regimes = [...new Set(d.regime)];
  const shading = regimes.map((regime, i) => ({
    label: `regime: ${regime}`,
    data: points(x, d.regime.map((r) => (r === regime ? peak * 1.05 : null))),
    fill: 'origin', borderWidth: 0, backgroundColor: ['rgba(31,95,168,0.08)', 'rgba(192,57,43,0.10)', 'rgba(46,139,87,0.10)', 'rgba(142,68,173,0.10)'][i % 4],
    pointRadius: 0, order: 10,
  }));
  addPlot(plots, {
    id: `${prefix}pressure`, title: 'Pressure and friction stress along the bite',
    description: 'x is the distance from the exit; the dashed line is the neutral point; shaded: lubrication regime',
    x: 'x from the exit [mm]', y: 'stress [MPa]',
    data: { datasets: [
      line('pressure [MPa]', points(x, d.pressure_MPa), 0),
      line('friction stress [MPa]', points(x, d.friction_MPa), 1),
      marker('neutral point', result.neutral_point_mm, 0, peak, '#333'),
      ...shading,
    ] },
  });
  addPlot(plots, {
    id: `${prefix}film`, title: 'Film thickness and contact ratio',
    x: 'x from the exit [mm]', y: 'film [µm]', y2: 'contact ratio [-]',
    data: { datasets: [
      line('film thickness [µm]', points(x, d.film_um), 2),
      line('contact ratio [-]', points(x, d.contact_ratio), 3, { yAxisID: 'y2' }),
    ] },
  });
  addPlot(plots, {
    id: `${prefix}speed`, title: 'Strip speed and roll speed',
    x: 'x from the exit [mm]', y: 'speed [m/s]',
    data: { datasets: [
      line('strip speed [m/s]', points(x, d.strip_speed_m_per_s), 4),
      line('roll speed [m/s]', [{ x: min(x), y: rollSpeed }, { x: max(x), y: rollSpeed }], 6, { borderDash: [4, 3] }),
      marker('neutral point', result.neutral_point_mm, min(d.strip_speed_m_per_s), max(d.strip_speed_m_per_s), '#333'),
    ] },
  });
}

function biteHeadline(r) {
  return [
    row('status', r.status), row('roll force', r.force_kN, 'kN'), row('roll torque', r.torque_kN_m, 'kN·m'),
    row('forward slip', r.forward_slip, '-'), row('mean friction coefficient', r.mean_friction_coefficient, '-'),
    row('inlet film', r.inlet_film_um, 'µm'), row('neutral point (from exit)', r.neutral_point_mm, 'mm'),
    row('contact length', r.contact_length_mm, 'mm'),
  ];
}

// The six masses of the stand's stack as the model numbers them (core/scenario.h, the field
// table's /mill/masses_t): the crossheads outermost, then the backup and the work rolls.
const stackMasses = ['m1 upper crosshead', 'm2 upper backup roll', 'm3 upper work roll',
  'm4 lower work roll', 'm5 lower backup roll', 'm6 lower crosshead'];

function modeShape(plots, mode, title) {
  if (!mode || !mode.shape) return;
  const type = mode.chatter_type ? `: chatter type ${chatterName(mode.chatter_type)}${mode.chatter_band && mode.chatter_band !== mode.chatter_type ? ` (its frequency band suggests ${chatterName(mode.chatter_band)})` : ''}` : '';
  addPlot(plots, {
    id: 'mode-shape', type: 'bar', title: `${title}${type}`, x: 'mass of the stack, top to bottom (docs/model.md §5)', y: 'relative amplitude',
    data: { labels: mode.shape.map((_, i) => stackMasses[i] || `m${i + 1}`), datasets: [{ label: `${fmt(mode.frequency_Hz)} Hz`, data: mode.shape, backgroundColor: color(1) }] },
  });
}

// `operating`: the scenario's roll speed, a line on both charts: the margin to the critical speed.
// `compare`: { pinned: a pinned stability's critical_speed, name, pinnedName }: drawn dashed
// beside this run's, the legend naming both runs.
function drawCritical(plots, critical, operating, compare) {
  if (!critical) return;
  const other = compare && compare.pinned;
  // Each run named once in a legend (the modes of the pinned run share one entry, dashed).
  const mine = (label, named = false) => (other ? `${label} — this run${named ? ` (${compare.name})` : ''}` : label);
  const theirs = (label, named = false) => `${label} — pinned${named ? ` (${compare.pinnedName})` : ''}`;
  const at = (low, high) => (Number.isFinite(operating)
    ? [{ ...marker(`operating speed (roll speed ${speedText(operating)})`, operating, low, high, '#2a7a2a'), borderDash: [2, 3], borderWidth: 3, pointStyle: 'line' }] : []);
  const speed = critical.critical_speed_m_per_s;
  const branches = critical.damping_branches || [];
  const all = branches.flatMap((b) => b.damping_ratio);
  const scan = critical.scan || [];
  if (!branches.length && !scan.length) {
    // detail "summary": the numbers without the curves; no empty charts
    panel(plots, 'The critical speed is in the table. A summary carries no damping branches or growth-rate scan: set detail to full to draw them.')
      .id = 'plot-stability-summary';
    return;
  }
  if (branches.length) addPlot(plots, {
    id: 'damping', title: `Damping ratio of each mode branch over rolling speed${other ? `: this run (${compare.name}, solid) and the pinned (${compare.pinnedName}, dashed)` : ''}`,
    description: 'below zero the mode grows: chatter; the dashed black line is the critical speed, the dotted green one the operating speed',
    x: 'rolling speed [m/s]', y: 'damping ratio [-]',
    data: { datasets: [
      ...branches.map((b, i) => line(`mode ${i + 1} (${fmt(b.frequency_Hz[0], 3)} Hz at ${speedText(b.speed_m_per_s[0], 3)})`, points(b.speed_m_per_s, b.damping_ratio), i)),
      ...(speed != null && all.length ? [marker(mine('critical speed'), speed, min(all), max(all), '#000')] : []),
      ...(all.length ? at(min(all), max(all)) : []),
      ...(other ? (other.damping_branches || []).map((b, i) => ({ ...line(`pinned (${compare.pinnedName}): each mode, dashed`, points(b.speed_m_per_s, b.damping_ratio), i, { borderDash: [6, 3], borderWidth: 1.5 }), mode: i + 1 })) : []),
      ...(other && other.critical_speed_m_per_s != null && all.length ? [{ ...marker(theirs('critical speed'), other.critical_speed_m_per_s, min(all), max(all), '#7f8c8d'), borderDash: [2, 2] }] : []),
    ] },
  });
  const growth = scan.map((s) => s.max_growth_rate_per_s);
  if (scan.length) addPlot(plots, {
    id: 'growth', title: 'Largest growth rate over rolling speed', x: 'rolling speed [m/s]', y: 'growth rate [1/s]',
    data: { datasets: [
      line(mine('max growth rate [1/s]', true), points(scan.map((s) => s.speed_m_per_s), growth), 1),
      ...(speed != null && growth.length ? [marker(mine('critical speed'), speed, min(growth), max(growth), '#000')] : []),
      ...(growth.length ? at(min(growth), max(growth)) : []),
      ...(other && (other.scan || []).length ? [line(theirs('max growth rate [1/s]', true), points(other.scan.map((q) => q.speed_m_per_s), other.scan.map((q) => q.max_growth_rate_per_s)), 6, { borderDash: [6, 3] })] : []),
      ...(other && other.critical_speed_m_per_s != null && growth.length ? [{ ...marker(theirs('critical speed'), other.critical_speed_m_per_s, min(growth), max(growth), '#7f8c8d'), borderDash: [2, 2] }] : []),
    ] },
  });
}


// ---- the tandem mill ----------------------------------------------------------------------------
// The three critical speeds (docs/model.md §12.7), named for a process engineer.
const crossingKinds = ['frozen', 'delay_independent', 'nominal_delay'];
const crossingNames = {
  frozen: 'frozen mill (the tension path alone)',
  delay_independent: 'delay-independent limit (some set of transport delays)',
  nominal_delay: 'nominal delays (the mill as it runs)',
};
const crossingShort = { frozen: 'frozen-mill', delay_independent: 'delay-independent', nominal_delay: 'nominal-delay' };
const outsideRange = "outside the model's range";
const yesNo = (value) => (value === true ? 'yes' : value === false ? 'no' : '—');
function rangeText(crossing) {
  const v = crossing && crossing.validity;
  if (!v) return '—';
  if (v.valid) return "inside the model's range";
  const why = [];
  if (!v.spring_law_valid) why.push("the spans' spring law fails (strip waves)");
  if (!v.quasi_static_bite_valid) why.push('the bite is not quasi-static');
  return `${outsideRange}${why.length ? `: ${why.join('; ')}` : ''}`;
}
const searchText = (crossing, options) => ({
  stable_in_range: `none up to ${speedText(options && options.speed_max_m_per_s)}`,
  unstable_at_lower_bound: 'unstable already at the lowest speed searched',
  no_steady_state: 'no steady state in the range',
  cancelled: 'cancelled',
}[crossing.status] || crossing.status);

// The root whose stands are marked and whose participation is drawn: the headline crossing,
// or the rightmost root at the mill speed when the critical speeds were not asked (or none lies
// inside the model's range).
function criticalRoot(result) {
  const c = result.critical_speeds;
  if (c && c.headline && c[c.headline]) {
    return { root: c[c.headline], what: `the headline critical speed, the ${crossingShort[c.headline]} crossing at ${speedText(c.critical_speed_m_per_s)}` };
  }
  const root = result.stability && result.stability.rightmost_root;
  if (!root) return null;
  return { root, what: `the rightmost root at the mill speed (${c ? "no crossing lies inside the model's range" : 'critical speeds not asked'})` };
}

function node(tag, className, text) {
  const n = document.createElement(tag);
  if (className) n.className = className;
  if (text !== undefined) n.textContent = text;
  return n;
}
// "label" and its value with the unit; the exact number in data-value (what a test compares).
function quantity(list, name, label, value, unit) {
  value = inShown(value, unit);
  unit = shown(unit).unit;
  const dd = node('dd');
  const number = node('span', 'num', fmt(value));
  number.dataset.quantity = name;
  if (typeof value === 'number') number.dataset.value = String(value);
  dd.append(number, unit ? ` ${unit}` : '');
  list.append(node('dt', '', label), dd);
}

// The stands in a row from the entry, the interstand tensions between them.
function millRow(plots, response, focus) {
  const r = response.result;
  const mill = response.tandem;
  const stands = r.steady_state.stands;
  const figure = panel(plots, 'The mill from entry to exit: roll speed, roll force and strip tension');
  figure.id = 'mill-figure';
  const key = node('p', 'help', focus
    ? `Marked: the moving stand (▲, thick red frame: it moves most) and the feeding stand (◆, dashed blue frame: its bite feeds the vibration most) of ${focus.what}.`
    : 'No root to mark: the mill has no steady state or no root was found.');
  key.id = 'mill-key';
  const row = node('ol', 'mill-row');
  row.id = 'mill-row';
  row.setAttribute('aria-label', 'The stands from the entry, with the strip between them');
  row.setAttribute('aria-describedby', key.id);
  const end = (title, tension, force, boundary) => {
    const item = node('li', 'mill-end');
    item.append(node('strong', '', title));
    const list = node('dl');
    quantity(list, 'tension', 'tension', tension, 'MPa');
    quantity(list, 'tension_force', 'strip force', force, 'kN');
    item.append(list, node('p', 'help', boundary));
    row.append(item);
  };
  const boundaryText = (b, what) => (b && b.boundary === 'constant' ? 'held at a constant tension' : `${what}, ${fmt(b && b.span_length_m)} m away`);
  if (stands.length) end('Entry', stands[0].back_tension_MPa, stands[0].back_tension_force_kN, boundaryText(mill.entry, 'bridle or uncoiler'));
  stands.forEach((stand, i) => {
    const item = node('li', 'mill-stand');
    item.dataset.stand = String(stand.stand);
    item.append(node('strong', 'mill-name', `Stand ${stand.stand}`));
    const list = node('dl');
    quantity(list, 'roll_speed', 'roll speed', stand.roll_speed_m_per_s, 'm/s');
    quantity(list, 'force', 'roll force', stand.force_kN, 'kN');
    quantity(list, 'exit_thickness', 'exit thickness', stand.exit_thickness_mm, 'mm');
    quantity(list, 'exit_speed', 'strip speed out', stand.exit_speed_m_per_s, 'm/s');
    item.append(list);
    if (stand.status !== 'ok') item.append(node('p', 'mill-flag', `no steady state: ${stand.status.replace(/_/g, ' ')}`));
    if (focus && focus.root.moving_stand === stand.stand) {
      item.classList.add('moving');
      const share = (focus.root.participation || [])[i];
      item.append(node('p', 'mill-flag moving', `▲ moving stand: moves most${share != null ? ` (${fmt(share * 100, 3)} % of the motion)` : ''}`));
    }
    if (focus && focus.root.feeding_stand === stand.stand) {
      item.classList.add('feeding');
      item.append(node('p', 'mill-flag feeding', '◆ feeding stand: its bite feeds the vibration most'));
    }
    row.append(item);
    if (i + 1 < stands.length) {
      const span = node('li', 'mill-span');
      span.dataset.span = String(i + 1);
      span.append(node('strong', '', `Strip, stand ${stand.stand} → ${stand.stand + 1}`));
      const spanList = node('dl');
      quantity(spanList, 'tension', 'tension', stand.front_tension_MPa, 'MPa');
      quantity(spanList, 'tension_force', 'strip force', stand.front_tension_force_kN, 'kN');
      quantity(spanList, 'length', 'span length', mill.spans.length_m[i], 'm');
      span.append(spanList);
      row.append(span);
    }
  });
  const last = stands[stands.length - 1];
  if (last) end('Exit', last.front_tension_MPa, last.front_tension_force_kN, boundaryText(mill.exit, 'coiler or exit bridle'));
  figure.append(key, row);
  const details = node('details');
  details.append(node('summary', '', 'The stands as a table'),
    numberTable('Steady state of each stand', ['stand', 'entry thickness [mm]', 'exit thickness [mm]', 'roll speed [m/s]', 'strip speed out [m/s]', 'roll force [kN]', 'torque [kN·m]', 'power [kW]', 'back tension [MPa]', 'front tension [MPa]', 'forward slip [-]', 'chatter mark spacing [mm]'],
      stands.map((s) => [`stand ${s.stand}`, s.entry_thickness_mm, s.exit_thickness_mm, s.roll_speed_m_per_s, s.exit_speed_m_per_s, s.force_kN, s.torque_kN_m, s.power_kW, s.back_tension_MPa, s.front_tension_MPa, s.forward_slip, s.chatter_mark_spacing_mm])));
  figure.append(details);
}

// The three critical speeds on one speed axis, one lane each, the headline and the mill speed.
function criticalSpeeds(plots, response) {
  const c = response.result.critical_speeds;
  if (!c) return;
  const lane = { nominal_delay: 1, delay_independent: 2, frozen: 3 };
  const laneNames = { 1: 'nominal delays', 2: 'delay-independent', 3: 'frozen mill' };
  const found = crossingKinds.filter((k) => c[k] && c[k].speed_m_per_s != null);
  const at = (k) => ({ x: c[k].speed_m_per_s, y: lane[k] });
  const sorted = (kinds) => kinds.map(at).sort((a, b) => a.x - b.x);
  const valid = found.filter((k) => c[k].validity && c[k].validity.valid);
  const invalid = found.filter((k) => !valid.includes(k));
  const speed = response.tandem.speed_m_per_s;
  const below = (c.outside_range_below || []).map((k) => crossingShort[k]);
  addPlot(plots, {
    id: 'critical-speeds', title: 'The three critical mill speeds', pointLegend: true,
    description: `circles: inside the model's range; crosses: ${outsideRange}; star: the headline (the lowest crossing inside the range); dashed line: the mill speed.${below.length ? ` Below the headline, ${outsideRange}: ${below.join(', ')}.` : ''}`,
    x: "mill speed, the last stand's roll speed [m/s]", y: 'which critical speed',
    yScale: { min: 0.5, max: 3.5, afterBuildTicks: (axis) => { axis.ticks = [1, 2, 3].map((value) => ({ value })); } },
    yTicks: { autoSkip: false, callback: (v) => laneNames[v] || '' },
    data: { datasets: [
      { label: "critical speed inside the model's range", data: sorted(valid), showLine: false, pointStyle: 'circle', pointRadius: 7, borderWidth: 2, borderColor: color(0), backgroundColor: color(0) },
      { label: `critical speed ${outsideRange}`, data: sorted(invalid), showLine: false, pointStyle: 'crossRot', pointRadius: 10, borderWidth: 3, borderColor: color(1), backgroundColor: color(1) },
      ...(c.headline ? [{ label: 'headline critical speed', data: [at(c.headline)], showLine: false, pointStyle: 'star', pointRadius: 16, borderWidth: 2, borderColor: '#000', backgroundColor: 'rgba(0,0,0,0)' }] : []),
      { ...marker("mill speed (the last stand's roll speed)", speed, 0.5, 3.5, '#333'), pointStyle: 'line' },
    ] },
  });
  const figure = panel(plots, 'The three critical speeds');
  const t = numberTable(`Critical speeds (searched ${fmt(inShown(response.options.speed_min_m_per_s, 'm/s'))}–${speedText(response.options.speed_max_m_per_s)})`,
    ['crossing', 'critical speed [m/s]', 'frequency [Hz]', 'moving stand', 'feeding stand', 'chatter band', 'chatter type', "model's range"],
    crossingKinds.filter((k) => c[k]).map((k) => [
      `${crossingNames[k]}${c.headline === k ? ' — headline' : ''}`,
      c[k].speed_m_per_s != null ? c[k].speed_m_per_s : searchText(c[k], response.options),
      c[k].frequency_Hz, c[k].moving_stand != null ? `stand ${c[k].moving_stand}` : '—', c[k].feeding_stand != null ? `stand ${c[k].feeding_stand}` : '—',
      chatterName(c[k].band), chatterName(c[k].chatter_type), c[k].speed_m_per_s != null ? rangeText(c[k]) : '—',
    ]));
  t.id = 'critical-speeds-table';
  [...t.tBodies[0].rows].forEach((tr, i) => { tr.dataset.kind = crossingKinds.filter((k) => c[k])[i]; });
  figure.append(t);
}

function participation(plots, focus) {
  if (!focus || !Array.isArray(focus.root.participation)) return;
  const p = focus.root.participation;
  addPlot(plots, {
    id: 'participation', type: 'bar', title: `Share of the motion by stand: ${focus.what}`,
    description: 'each stand\'s share of the motion of that root, mass-weighted, summing to 1; the moving stand has the largest',
    x: 'stand (from the entry)', y: 'share of the motion [-]',
    data: { labels: p.map((_, i) => `stand ${i + 1}`), datasets: [{ label: 'share of the motion [-]', data: p, backgroundColor: color(0) }] },
  });
}

// ρ broken into its factors per span at its peak (stability.margin_factors, docs/model.md
// §12.5), the span carrying the largest share named; and whether the peak's frequency lies
// inside the model's range (stability.margin_validity).
function marginFactors(plots, stability) {
  const factors = stability && stability.margin_factors;
  if (!Array.isArray(factors) || !factors.length) return;
  const figure = panel(plots, "The regenerative margin ρ's factors, span by span, at its peak");
  figure.id = 'margin-factors';
  const top = factors.reduce((best, f) => ((f.worst_input_share ?? -1) > (best.worst_input_share ?? -1) ? f : best));
  const spanName = (i) => `stand ${i} → ${i + 1}`;
  const sentence = node('p', 'margin-sentence');
  sentence.id = 'margin-sentence';
  sentence.dataset.span = String(top.span);
  sentence.textContent = `ρ = ${fmt(stability.regenerative_margin)} at ${fmt(stability.margin_frequency_Hz)} Hz: the span from stand ${top.span} to stand ${top.span + 1} carries the largest share of the loop's worst input (${fmt(top.worst_input_share * 100, 3)} %).`;
  const t = numberTable(`Factors of ρ at ${fmt(stability.margin_frequency_Hz)} Hz (the receiving stand: the one the span feeds)`,
    ['span', "share of the loop's worst input [-]", 'its own tension loop |M_ii| [-]', 'thickness path on |M_i+1,i| [-]',
      "receiving stand's force gain dF/dy1 [kN/mm]", "receiving stand's entry speed gain du1/dy1 [1/s]", "receiving stand's compliance at the peak [µm/kN]"],
    factors.map((f) => [spanName(f.span), f.worst_input_share, f.tension_loop_gain, f.thickness_gain ?? '— (last span)',
      f.bite_force_gain_kN_per_mm, f.bite_entry_speed_gain_per_s, f.compliance_um_per_kN]));
  t.id = 'margin-factors-table';
  [...t.tBodies[0].rows].forEach((tr, i) => { tr.dataset.span = String(factors[i].span); });
  figure.append(sentence, t);
  const v = stability.margin_validity;
  if (v) {
    const why = [];
    if (!v.spring_law_valid) why.push("the spans' spring law fails (strip waves)");
    if (!v.quasi_static_bite_valid) why.push('the bite is not quasi-static');
    const note = node('p', 'help', `ρ's peak frequency ${v.valid ? "lies inside the model's range" : `lies ${outsideRange}${why.length ? `: ${why.join('; ')}` : ''}`}`
      + ` (bite transit over the period, stand by stand: ${(v.bite_transit_ratio || []).map((x) => fmt(x, 3)).join(', ') || '—'};`
      + ` spring-law error, span by span: ${(v.spring_law_error || []).map((x) => fmt(x, 3)).join(', ') || '—'}).`);
    note.id = 'margin-validity';
    note.dataset.valid = String(v.valid);
    figure.append(note);
  }
}

// ρ and the rightmost root's growth rate against mill speed: the mill of the answer swept over
// /speed_m_per_s in stability mode (tandem_sweep), run as a job whose finished speeds are drawn
// as they arrive, with the three critical speeds of the answer as vertical lines.
const millSpeedLabel = "mill speed, the last stand's roll speed [m/s]";
function speedRange(response) {
  const c = response.result.critical_speeds || {};
  const o = response.options || {};
  const found = crossingKinds.map((k) => c[k] && c[k].speed_m_per_s).filter((v) => v != null);
  const high = Math.max(response.tandem.speed_m_per_s, ...found) * 1.15;
  const to = Number(Math.min(o.speed_max_m_per_s ?? 100, Math.max(high, 2)).toPrecision(3));
  const from = Number(Math.min(o.speed_min_m_per_s ?? 1, to / 2).toPrecision(3));
  // A modest number of speeds: a point costs ~0.02 s at two stands, ~1 s at five.
  const count = response.tandem.exit_thickness_mm.length <= 3 ? 25 : 13;
  return { from, to, count };
}

// `points`: the sweep's points, null where a running job has not computed one yet; `xs`: the
// speeds asked (those of the points not yet computed).
function speedSweepDatasets(response, points, xs = []) {
  const speeds = points.map((p, i) => (p ? p.value_m_per_s : xs[i] ?? null));
  const done = points.filter(Boolean);
  const rho = (p) => (p && p.regenerative_margin != null ? p.regenerative_margin : null);
  const growth = (p) => (p ? p.growth_rate_per_s : null);
  const at = (pick, inRange) => points.map((p, i) => ({ x: speeds[i], y: p && p.in_model_range === inRange ? pick(p) : null })).filter((q) => q.x != null && q.y != null);
  const datasets = [
    line('regenerative margin ρ [-]', points.map((p, i) => ({ x: speeds[i], y: rho(p) })).filter((q) => q.x != null), 0, { pointRadius: 3, order: 2 }),
    line('growth rate of the rightmost root [1/s]', points.map((p, i) => ({ x: speeds[i], y: growth(p) })).filter((q) => q.x != null), 1, { pointRadius: 3, yAxisID: 'y2', order: 2 }),
    { label: "rightmost root outside the model's range", data: at(growth, false), yAxisID: 'y2', showLine: false, pointStyle: 'crossRot', pointRadius: 7, borderWidth: 2, borderColor: color(1), backgroundColor: color(1), order: 1 },
  ];
  if (!done.length) return datasets;
  const lo = Math.min(...done.map((p) => p.value_m_per_s));
  const hi = Math.max(...done.map((p) => p.value_m_per_s));
  const g = done.map(growth).filter((v) => v != null);
  const gLow = Math.min(0, ...g);
  const gHigh = Math.max(0, ...g);
  const rhos = done.map(rho).filter((v) => v != null);
  if (rhos.length) datasets.push({ label: 'ρ = 1 (below: stable whatever the delays)', data: [{ x: lo, y: 1 }, { x: hi, y: 1 }], borderColor: color(0), borderDash: [2, 3], borderWidth: 1, pointRadius: 0, order: 3 });
  datasets.push({ label: 'growth rate 0 (above: the mill chatters)', data: [{ x: lo, y: 0 }, { x: hi, y: 0 }], yAxisID: 'y2', borderColor: color(1), borderDash: [2, 3], borderWidth: 1, pointRadius: 0, order: 3 });
  const mill = response.tandem.speed_m_per_s;
  datasets.push({ ...marker(`mill speed ${speedText(mill)} (the operating speed)`, mill, gLow, gHigh, '#2a7a2a', 'y2'), borderDash: [2, 3], borderWidth: 3, pointRadius: 0, order: 0 });
  const c = response.result.critical_speeds;
  if (c) {
    const colours = { frozen: color(2), delay_independent: color(3), nominal_delay: color(4) };
    for (const k of crossingKinds) {
      const speed = c[k] && c[k].speed_m_per_s;
      if (speed == null) continue;
      const headline = c.headline === k;
      const range = c[k].validity && c[k].validity.valid ? '' : `, ${outsideRange}`;
      datasets.push({
        ...marker(`${crossingShort[k]} critical speed ${speedText(speed)}${headline ? ' — headline' : ''}${range}`, speed, gLow, gHigh, headline ? '#000' : colours[k], 'y2'),
        borderWidth: headline ? 4 : 2, borderDash: headline ? [] : [6, 4], pointRadius: 0, order: 0, kind: k,
      });
    }
  }
  return datasets;
}

function speedSweep(plots, response) {
  if (!response.result.steady_state || response.result.steady_state.status !== 'ok') return;
  const controls = panel(plots, 'Margin and growth rate against mill speed');
  controls.id = 'speed-sweep-controls';
  const range = speedRange(response);
  const inputs = {};
  const row = node('div', 'row');
  for (const [key, label, step] of [['from', 'from [m/s]', 'any'], ['to', 'to [m/s]', 'any'], ['count', 'speeds', '1']]) {
    const input = Object.assign(document.createElement('input'), { id: `speed-sweep-${key}`, type: 'number', step, min: key === 'count' ? '2' : '0.01', value: String(range[key]) });
    if (key === 'count') input.max = '200';
    const l = node('label', '', `${label} `);
    l.htmlFor = input.id;
    row.append(l, input);
    inputs[key] = input;
  }
  const again = node('button', '', 'Draw again');
  again.type = 'button';
  again.id = 'speed-sweep-run';
  const status = node('span', 'muted');
  status.id = 'speed-sweep-status';
  status.setAttribute('role', 'status');
  row.append(again, status);
  controls.append(node('p', 'help', "The mill of this answer at each speed (a mill sweep of its speed, stability only, run as a job): the regenerative margin ρ (left, log scale; only where the frozen mill is stable) and the rightmost root's growth rate (right). Vertical lines: the three critical speeds of this answer, the headline thick and solid."), row);
  const chart = addPlot(plots, {
    id: 'speed-sweep', wide: true, title: "Regenerative margin ρ and the rightmost root's growth rate against mill speed",
    description: 'left axis: ρ, log scale; right axis: growth rate; crosses: the rightmost root lies outside the model\'s range; vertical lines: the critical speeds',
    x: millSpeedLabel, y: 'regenerative margin ρ [-]', y2: 'growth rate of the rightmost root [1/s]', yScale: { type: 'logarithmic' }, pointLegend: false,
    data: { datasets: speedSweepDatasets(response, []) },
  });
  // The job: { path, state, polling }. Cancelled (DELETE) only while it runs, and never while a
  // poll of it is on its way (the poll's answer decides): a DELETE on a job that has just
  // finished removes it, and a poll crossing that DELETE would answer 404.
  let job = null;
  let stopped = false;
  const cancel = (j) => { if (j && j.path && ['queued', 'running'].includes(j.state)) call('DELETE', j.path).catch(() => {}); };
  const stop = () => {
    stopped = true;
    if (job && !job.polling) cancel(job);
  };
  onClear(stop);
  const draw = (points, xs) => setDatasets(chart, speedSweepDatasets(response, points, xs));
  const start = async () => {
    stop();
    stopped = false;
    const options = { parameter: '/speed_m_per_s', quantity: 'stability', range: { from: Number(inputs.from.value), to: Number(inputs.to.value), count: Number(inputs.count.value) } };
    const body = { analysis: 'tandem_sweep', tandem: response.tandem, options };
    const mine = { path: null, state: 'queued' };
    job = mine;
    delete chart.canvas.dataset.state;
    status.textContent = 'starting…';
    try {
      const { location, body: created } = await call('POST', '/v1/jobs', body);
      mine.path = location || `/v1/jobs/${created.id}`;
      if (stopped || job !== mine) { cancel(mine); return; }
      let shown = -1;
      for (;;) {
        if (stopped || job !== mine) return;  // cancelled by stop() while waiting
        mine.polling = true;
        const j = await getJson(mine.path);
        mine.polling = false;
        mine.state = j.state;
        if (stopped || job !== mine) { cancel(mine); return; }
        if (j.state === 'succeeded') {
          const result = j.result.result || j.result;
          draw(result.points);
          chart.canvas.dataset.state = 'done';
          status.textContent = `${result.points.length} speeds, job succeeded`;
          return;
        }
        if (['failed', 'cancelled'].includes(j.state)) {
          status.textContent = `job ${j.state}${j.problem ? `: ${j.problem.detail}` : ''}`;
          return;
        }
        const partial = j.partial_result;
        if (partial && Array.isArray(partial.points) && partial.points.length !== shown) {
          shown = partial.points.length;
          const list = Array.from({ length: options.range.count }, () => null);
          for (const p of partial.points) if (p.index < list.length) list[p.index] = p.point;
          draw(list, optionValues(options));
        }
        status.textContent = `running: ${j.points_done || 0} of ${j.points_total || options.range.count} speeds`;
        await new Promise((resolve) => setTimeout(resolve, 250));
      }
    } catch (error) {
      if (!stopped) status.textContent = `failed: ${error.message}`;
    }
  };
  again.addEventListener('click', start);
  start();
}

// The whole mill in time after a gap kick (result.time_series, docs/model.md §12.9): each
// stand's gap change and roll force, and the strip tension of each span; how the run ended.
const timeStates = {
  ok: 'the window was simulated',
  slack_span: 'a span went slack (its force reached zero)',
  contact_lost: 'a stand lost contact with the strip',
  skidding: 'the rolls skid on the strip',
  solver_failure: 'the integrator failed',
  step_budget: 'the step budget ran out',
  cancelled: 'cancelled',
  invalid: 'invalid',
};
function timeSeries(plots, ts, nStands) {
  if (!ts) return;
  const figure = panel(plots, 'The mill in time after a gap kick');
  figure.id = 'time-series';
  const spanText = (span) => (span === 0 ? 'the entry span' : span === nStands ? 'the exit span' : `the span from stand ${span} to stand ${span + 1}`);
  const where = [ts.span != null ? spanText(ts.span) : '', ts.stand != null ? `stand ${ts.stand}` : ''].filter(Boolean).join(', ');
  const state = node('p', ts.status === 'ok' ? '' : 'mill-flag', `Result: ${timeStates[ts.status] || ts.status}${where ? ` (${where})` : ''}`
    + `${ts.end_time_s != null ? `, at ${fmt(ts.end_time_s)} s` : ''}${ts.message && ts.message !== 'ok' ? ` — ${ts.message}` : ''}.`);
  state.id = 'time-series-state';
  state.dataset.status = ts.status;
  const kick = node('p', 'help', `A kick of ${fmt(ts.kick_um)} µm at stand ${ts.kick_stand ?? '—'} at t = 0; ${ts.steps} integrator steps. ${ts.range_note || ''}`);
  figure.append(state, kick);
  const stands = ts.stands || [];
  if (!stands.length) return;
  const per = (key) => stands.map((s, i) => line(`stand ${s.stand}`, points(s.series.time_s, s.series[key]), i));
  addPlot(plots, { id: 'time-gap', title: 'Roll gap change of each stand after the kick', x: 'time [s]', y: 'roll gap change [µm]', data: { datasets: per('gap_change_um') } });
  addPlot(plots, { id: 'time-force', title: 'Roll force of each stand', x: 'time [s]', y: 'roll force [kN]', data: { datasets: per('force_kN') } });
  const first = stands[0];
  const last = stands[stands.length - 1];
  const tension = [
    line('entry span (stand 1 back tension)', points(first.series.time_s, first.series.back_tension_MPa), 6, { borderDash: [4, 3] }),
    ...stands.slice(0, -1).map((s, i) => line(`span stand ${s.stand} → ${s.stand + 1}`, points(s.series.time_s, s.series.front_tension_MPa), i)),
    line(`exit span (stand ${last.stand} front tension)`, points(last.series.time_s, last.series.front_tension_MPa), 7, { borderDash: [4, 3] }),
  ];
  addPlot(plots, { id: 'time-tension', title: 'Strip tension in each span', x: 'time [s]', y: 'strip tension [MPa]', data: { datasets: tension } });
}

// The speed limit (docs/model.md §13): every checked limit on one speed axis, one lane each —
// the speeds at which it is met as a bar, the binding ones thicker and named — the permitted
// window on a lane of its own, the critical speed's uncertainty as a band on the chatter lane
// (95 % lower bound to the mean), and the operating and advised speeds as dashed lines.
const limitNames = { force: 'roll force', torque: 'torque', power: 'motor power', skid: 'skid (forward slip)', chatter: 'chatter', steady_state: 'steady state' };
// A mill's (tandem_speed_limit) names each limit with its stand and speaks of the mill speed.
const limitLane = (l, mill) => `${limitNames[l.limit] || l.limit}${mill && l.stand != null ? ` · stand ${l.stand}` : ''}`;
function speedLimitAxis(plots, response, mill = false) {
  const r = response.result;
  const o = response.options || {};
  const lo = o.speed_min_m_per_s;
  const hi = o.speed_max_m_per_s;
  const checked = (r.limits || []).filter((l) => l.limit !== 'steady_state');
  const lanes = [...checked.map((l) => limitLane(l, mill)), 'permitted window'];
  const top = lanes.length;
  const binding = (l) => (mill
    ? (l.limit === r.binding_limit && l.stand === r.binding_stand) || (l.limit === r.binding_min && l.stand === r.binding_min_stand)
    : l.limit === r.binding_limit || l.limit === r.binding_min);
  const segment = (label, from, to, y, i, extra = {}) => ({
    label, data: [{ x: from, y }, { x: to, y }], borderColor: color(i), backgroundColor: color(i), borderWidth: 8, pointRadius: 0, ...extra,
  });
  const datasets = [];
  checked.forEach((l, k) => {
    // A limit met nowhere in the range has neither end and is not met at the operating speed.
    const from = l.lower_speed_m_per_s ?? lo;
    const to = l.upper_speed_m_per_s ?? hi;
    if (l.lower_speed_m_per_s == null && l.upper_speed_m_per_s == null && !l.met_at_operating) return;
    const name = limitLane(l, mill);
    datasets.push(segment(binding(l) ? `${name} permits (binding)` : `${name} permits`, from, to, k + 1, k,
      binding(l) ? { borderWidth: 16, borderColor: '#d0021b', backgroundColor: '#d0021b' } : {}));
  });
  const u = r.uncertainty;
  const chatterLane = checked.findIndex((l) => l.limit === 'chatter') + 1;
  if (u && u.propagated && chatterLane > 0 && u.lower_bound_m_per_s != null) {
    datasets.push({ ...segment(`critical speed: ${fmt(100 * u.confidence, 3)} % lower bound to the mean (σ ${speedText(u.standard_deviation_m_per_s, 3)})`,
      u.lower_bound_m_per_s, u.critical_speed_m_per_s, chatterLane + 0.25, 5, { borderWidth: 10, borderColor: 'rgba(245,166,35,0.6)', backgroundColor: 'rgba(245,166,35,0.6)' }) });
  }
  if (r.status === 'ok') datasets.push(segment('permitted window', r.window_min_m_per_s, r.window_max_m_per_s, top, 3, { borderColor: '#2a7a2a', backgroundColor: '#2a7a2a' }));
  datasets.push({ ...marker('operating speed', r.operating_speed_m_per_s, 0.5, top + 0.5, '#333'), pointStyle: 'line' });
  if (r.advised_speed_m_per_s != null) datasets.push({ ...marker('advised speed', r.advised_speed_m_per_s, 0.5, top + 0.5, '#d0021b'), pointStyle: 'line' });
  addPlot(plots, {
    id: 'speed-limits', title: 'The limits on one speed axis', wide: true,
    description: 'bars: the speeds at which each limit is met (thick red: the binding limit); orange band: the critical speed from its lower bound to its mean; dashed: the operating and advised speeds',
    x: mill ? "mill speed (the last stand's roll speed) [m/s]" : 'roll speed [m/s]', y: 'limit',
    yScale: { min: 0.5, max: top + 0.5, afterBuildTicks: (axis) => { axis.ticks = lanes.map((_, i) => ({ value: i + 1 })); } },
    yTicks: { autoSkip: false, callback: (v) => lanes[v - 1] || '' },
    data: { datasets },
  });
  const figure = panel(plots, 'Each limit');
  figure.append(numberTable(`Each checked limit at the ${mill ? 'mill' : 'operating'} speed and its own speeds`,
    ['limit', 'unit', 'limit value', `at the ${mill ? 'mill' : 'operating'} speed`, 'utilisation', 'met', 'lowest speed', 'highest speed'],
    (r.limits || []).map((l) => [limitLane(l, mill), l.unit === '1' ? '-' : l.unit, l.value, l.at_operating, l.utilisation, yesNo(l.met_at_operating), l.lower_speed_m_per_s, l.upper_speed_m_per_s])));
}

// A batch's rows (docs/http-api.md, "Batches") as a table of coils, sorted by any column by its
// header's button (first by the speed margin, the tightest coil on top); a coil's problem in
// its row. The numbers keep their exact values in data-value, as numberTable's.
function batchTable(plots, result) {
  const speedLimit = result.analysis === 'speed_limit';
  const keys = speedLimit
    ? [['speed_margin_m_per_s', 'margin [m/s]'], ['utilisation', 'utilisation [-]'], ['operating_speed_m_per_s', 'operating speed [m/s]'],
      ['advised_speed_m_per_s', 'advised speed [m/s]'], ['binding_limit', 'binding limit'], ['critical_speed_m_per_s', 'critical speed [m/s]'],
      ['critical_speed_sd_m_per_s', 'its σ [m/s]']]
    : [...new Set(result.items.flatMap((r) => Object.keys(r.headline || {})))].slice(0, 8).map((k) => [k, k]);
  const columns = [['label', 'coil'], ['status', 'status'], ...keys, ['problem', 'problem']];
  const value = (item, key) => {
    if (key === 'label' || key === 'status') return item[key];
    if (key === 'problem') {  // the first violation where there is one: what to fix, and where
      const p = item.problem;
      const first = p && Array.isArray(p.errors) && p.errors[0];
      return p ? (first ? `${first.pointer}: ${first.detail}` : p.detail || p.title) : null;
    }
    return item.headline ? item.headline[key] ?? null : null;
  };
  const figure = panel(plots, `The coils (${result.items.length})`);
  const t = document.createElement('table');
  t.id = 'batch-table';
  const caption = document.createElement('caption');
  caption.textContent = 'One row per coil; the buttons in the header sort by that column';
  t.append(caption);
  const head = t.createTHead().insertRow();
  const body = t.createTBody();
  let order = { key: speedLimit ? 'speed_margin_m_per_s' : 'label', ascending: true };
  const fill = () => {
    // Nulls (a failed coil, a figure not asked) last whichever way it sorts.
    const rows = [...result.items].sort((a, b) => {
      const x = value(a, order.key);
      const y = value(b, order.key);
      if (x === null || y === null) return (x === null) - (y === null);
      const c = typeof x === 'number' && typeof y === 'number' ? x - y : String(x).localeCompare(String(y));
      return order.ascending ? c : -c;
    });
    body.replaceChildren();
    for (const item of rows) {
      const tr = body.insertRow();
      tr.dataset.index = String(item.index);
      columns.forEach(([key], i) => {
        const cell = document.createElement(i === 0 ? 'th' : 'td');
        if (i === 0) cell.scope = 'row';
        const v = inShown(value(item, key), /_m_per_s$/.test(key) ? 'm/s' : '');
        cell.textContent = typeof v === 'number' ? fmt(v) : v === true ? 'yes' : v === false ? 'no' : v ?? '—';
        if (typeof v === 'number') cell.dataset.value = String(v);
        tr.append(cell);
      });
    }
    [...head.cells].forEach((th, i) => th.setAttribute('aria-sort', columns[i][0] === order.key ? (order.ascending ? 'ascending' : 'descending') : 'none'));
  };
  for (const [key, title] of columns) {
    const th = document.createElement('th');
    th.scope = 'col';
    const button = document.createElement('button');
    button.type = 'button';
    button.className = 'sort';
    button.id = `batch-sort-${key.replace(/[^A-Za-z0-9]+/g, '-')}`;
    button.textContent = labelShown(title);
    button.addEventListener('click', () => { order = { key, ascending: order.key === key ? !order.ascending : true }; fill(); });
    th.append(button);
    head.append(th);
  }
  fill();
  const scroll = document.createElement('div');
  scroll.className = 'table-scroll';
  // Focusable, so a keyboard can scroll it (axe: scrollable-region-focusable).
  scroll.tabIndex = 0;
  scroll.setAttribute('role', 'region');
  scroll.setAttribute('aria-label', 'The coils');
  scroll.append(t);
  figure.append(scroll);
}

export const views = {
  roll_gap: {
    render(response, plots) {
      const r = response.result;
      drawBite(plots, r, response.scenario.rolls.speed_m_per_s);
      return biteHeadline(r);
    },
  },
  stability: {
    render(response, plots, { pinned, name } = {}) {
      const r = response.result;
      const c = r.critical_speed || {};
      // A pinned stability (another run's) beside this one.
      const other = pinned && pinned.response !== response && pinned.response.analysis === 'stability' && pinned.response.result.critical_speed;
      drawCritical(plots, r.critical_speed, response.scenario ? response.scenario.rolls.speed_m_per_s : r.speed_m_per_s,
        other ? { pinned: other, name, pinnedName: pinned.name } : null);
      const mode = c.unstable_mode || r.least_damped_mode;
      modeShape(plots, mode, c.unstable_mode ? 'Shape of the mode that turns unstable' : 'Shape of the least-damped mode');
      return [
        row('stable at the scenario speed', r.stable), row('rolling speed', r.speed_m_per_s, 'm/s'),
        row('critical speed', c.critical_speed_m_per_s, 'm/s'), row('search status', c.status),
        row('unstable mode frequency', c.unstable_mode && c.unstable_mode.frequency_Hz, 'Hz'),
        row('chatter type of the unstable mode', chatterName(c.unstable_mode && c.unstable_mode.chatter_type)),
        row('chatter type of the least-damped mode', chatterName(r.least_damped_mode && r.least_damped_mode.chatter_type)),
        row('least-damped mode', r.least_damped_mode && r.least_damped_mode.frequency_Hz, 'Hz'),
        row('its damping ratio', r.least_damped_mode && r.least_damped_mode.damping_ratio, '-'),
        row('strip stiffness', r.strip_stiffness_GN_per_m, 'GN/m'),
      ];
    },
  },
  amplitude: {
    render(response, plots) {
      const p = response.result.points;
      const v = p.map((q) => q.speed_m_per_s);
      addPlot(plots, {
        id: 'amplitude', title: 'Vibration amplitude over rolling speed', x: 'rolling speed [m/s]', y: 'amplitude [µm]', y2: 'force amplitude [kN]',
        data: { datasets: [
          line('gap amplitude [µm]', points(v, p.map((q) => q.gap_amplitude_um)), 0, { pointRadius: 4 }),
          line('upper roll amplitude [µm]', points(v, p.map((q) => q.upper_roll_amplitude_um)), 1, { pointRadius: 4 }),
          line('force amplitude [kN]', points(v, p.map((q) => q.force_amplitude_kN)), 2, { pointRadius: 4, yAxisID: 'y2' }),
        ] },
      });
      p.filter((q) => q.time_series).forEach((q, i) => addPlot(plots, {
        id: `series-${i}`, title: `Time series at ${speedText(q.speed_m_per_s)}`, x: 'time [s]', y: 'work-roll gap change [µm]', y2: 'roll force change [kN]',
        data: { datasets: [
          line('gap change [µm]', points(q.time_series.time_s, q.time_series.work_roll_gap_change_um), 0),
          line('force change [kN]', points(q.time_series.time_s, q.time_series.roll_force_change_kN), 2, { yAxisID: 'y2' }),
        ] },
      }));
      return p.map((q) => row(`gap amplitude at ${speedText(q.speed_m_per_s)} (${q.status})`, q.gap_amplitude_um, 'µm'));
    },
  },
  tension_cycle: {
    render(response, plots) {
      const r = response.result;
      r.phases.forEach((phase, i) => {
        if (i === 0) drawBite(plots, phase.roll_gap, response.scenario.rolls.speed_m_per_s, `phase${i}-`);
      });
      const withDistribution = r.phases.filter((p) => p.roll_gap.distribution);
      if (withDistribution.length) {
        addPlot(plots, {
          id: 'phases', title: 'Pressure along the bite at each phase of the back tension', x: 'x from the exit [mm]', y: 'pressure [MPa]',
          data: { datasets: withDistribution.map((p, i) => line(`phase ${p.phase} (back tension ${fmt(p.back_tension_MPa)} MPa)`, points(p.roll_gap.distribution.x_mm, p.roll_gap.distribution.pressure_MPa), i)) },
        });
      }
      return [row('status', r.status), ...r.phases.map((p) => row(`force at phase ${p.phase} (back tension ${fmt(p.back_tension_MPa)} MPa)`, p.roll_gap.force_kN, 'kN'))];
    },
  },
  sweep: {
    job: true,
    // A running job's finished points (partial_result) as a result with gaps.
    partial(request, partial) {
      const options = request.options || {};
      const xs = optionValues(options);
      const found = new Map(partial.points.map((p) => [p.index, p.point]));
      const valueName = [...found.values()].map((p) => Object.keys(p).find((k) => /^value(_|$)/.test(k))).find(Boolean) || 'value';
      return {
        parameter: options.parameter, unit: '', value_name: valueName, quantity: options.quantity || 'critical_speed',
        points: xs.map((x, i) => found.get(i) || { [valueName]: x, missing: true }),
        chatter_type_changes: [],
      };
    },
    render(response, plots, { doc, speed, pinned, name: thisRun } = {}) {
      const r = response.result;
      const critical = r.quantity !== 'amplitude';
      // A pinned sweep of the same field and quantity (another run's) beside this one.
      const other = pinned && pinned.response !== response && pinned.response.analysis === 'sweep' && pinned.response.result.parameter === r.parameter
        && pinned.response.result.quantity === r.quantity ? pinned : null;
      const mine = (label) => (other ? `${label} — this run (${thisRun})` : label);
      const name = r.value_name || 'value';
      const v = r.points.map((p) => p[name]);
      const y = (key) => r.points.map((p) => (p.missing ? null : p[key]));
      const speeds = y('critical_speed_m_per_s');
      const typed = critical ? Object.entries(chatterTypes).map(([type, style], k) => {
        const data = r.points.map((p, i) => ({ x: v[i], y: speeds[i] })).filter((_, i) => r.points[i].chatter_type === type);
        return { label: `chatter type ${style.name}`, data, pointStyle: style.pointStyle, pointRadius: 8, borderWidth: 2, showLine: false, order: 0, borderColor: color(k + 2), backgroundColor: 'rgba(255,255,255,0.6)' };
      }).filter((d) => d.data.length) : [];
      const changes = (r.chatter_type_changes || []).map((c) => (c.from + c.to) / 2);
      const known = speeds.filter((s) => s !== null);
      // The operating speed against the critical speeds: the scenario's roll speed, or the swept
      // value itself when the roll speed is what is swept.
      const operating = response.scenario && response.scenario.rolls ? response.scenario.rolls.speed_m_per_s : speed;
      const xs = v.filter((x) => x != null);
      const operatingLine = !critical || !xs.length ? [] : r.parameter === '/rolls/speed_m_per_s'
        ? [{ label: 'operating speed (the swept roll speed)', data: [{ x: min(xs), y: min(xs) }, { x: max(xs), y: max(xs) }], borderColor: '#2a7a2a', borderDash: [2, 3], borderWidth: 3, pointRadius: 0, pointStyle: 'line', order: 2 }]
        : Number.isFinite(operating)
          ? [{ label: `operating speed (roll speed ${speedText(operating)})`, data: [{ x: min(xs), y: operating }, { x: max(xs), y: operating }], borderColor: '#2a7a2a', borderDash: [2, 3], borderWidth: 3, pointRadius: 0, pointStyle: 'line', order: 2 }]
          : [];
      addPlot(plots, {
        id: 'sweep', title: `${critical ? 'Critical speed' : 'Amplitude'} over ${fieldName(doc, r.parameter).toLowerCase()}${response.partial ? ' (running: the finished points)' : ''}`,
        description: critical ? 'symbols: the chatter type of the mode that goes unstable; dashed red lines: the chatter type changes; dotted green line: the operating speed' : '',
        x: axisLabel(doc, r.parameter, r.unit), pointLegend: critical,
        y: critical ? 'critical speed [m/s]' : 'gap amplitude [µm]', y2: critical ? 'chatter frequency [Hz]' : undefined,
        data: { datasets: critical ? [
          line(mine('critical speed [m/s]'), points(v, speeds), 0, { pointRadius: 3, order: 1 }),
          ...(other ? [line(`critical speed [m/s] — pinned (${other.name})`, points(other.response.result.points.map((p) => p[other.response.result.value_name || 'value']), other.response.result.points.map((p) => p.critical_speed_m_per_s)), 6, { pointRadius: 3, pointStyle: 'rectRot', borderDash: [6, 3], order: 1 })] : []),
          line('frequency of the unstable mode [Hz]', points(v, y('frequency_Hz')), 1, { pointRadius: 3, yAxisID: 'y2', order: 1, borderDash: [2, 2] }),
          ...typed,
          ...(known.length ? changes.map((x) => ({ ...marker('chatter type changes', x, min(known), max(known), '#d0021b'), pointRadius: 0 })) : []),
          ...operatingLine,
        ] : [line(mine('gap amplitude [µm]'), points(v, y('gap_amplitude_um')), 0, { pointRadius: 3 }),
          ...(other ? [line(`gap amplitude [µm] — pinned (${other.name})`, points(other.response.result.points.map((p) => p[other.response.result.value_name || 'value']), other.response.result.points.map((p) => p.gap_amplitude_um)), 6, { pointRadius: 3, borderDash: [6, 3] })] : [])] },
      });
      const rows = [row('parameter', fieldName(doc, r.parameter)), row('values', r.points.filter((p) => !p.missing).length), row('quantity', r.quantity)];
      if (critical && !response.partial) {  // the changes come with the complete result
        rows.push(row('chatter type changes', (r.chatter_type_changes || []).length));
        for (const c of r.chatter_type_changes || []) rows.push([`between ${fmt(c.from)} and ${fmt(c.to)}`, `${chatterName(c.from_chatter_type)} → ${chatterName(c.to_chatter_type)}`, '']);
      }
      return rows;
    },
  },
  map: {
    job: true,
    partial(request, partial) {
      const axes = ((request.options || {}).parameters || []).map((a) => ({ parameter: a.parameter, unit: '', values: optionValues(a) }));
      const count = axes.length === 2 ? axes[0].values.length * axes[1].values.length : 0;
      const cells = Array.from({ length: count }, () => null);
      for (const p of partial.points) if (p.index < count) cells[p.index] = p.point;
      return { parameters: axes, cells, chatter_type_changes: [] };
    },
    render(response, plots, { doc, speed } = {}) {
      const r = response.result;
      const [rowsAxis, columnsAxis] = r.parameters;
      const nc = columnsAxis.values.length;
      const rolling = response.scenario ? response.scenario.rolls.speed_m_per_s : speed;
      const classes = {
        stable_in_range: { symbol: 'S', fill: [236, 236, 236] },
        unstable_at_lower_bound: { symbol: 'U', fill: [90, 90, 90] },
        no_steady_state: { symbol: '×', fill: [255, 255, 255] },
      };
      // A cell says its critical speed (in the units shown) and the chatter type's symbol; one
      // without a critical speed its class's letter.
      const cells = r.cells.map((c) => {
        if (!c) return null;
        const extra = classes[c.status] || {};
        const symbol = c.chatter_type ? chatterTypes[c.chatter_type].symbol : extra.symbol || '?';
        const value = inShown(c.critical_speed_m_per_s, 'm/s');
        return { value, symbol, text: value != null ? `${fmt(value, 3)} ${symbol}` : symbol, fill: extra.fill, cell: c };
      });
      // The axes in the units shown (a viscosity in mPa·s in plant units).
      const axis = (a) => {
        const title = axisLabel(doc, a.parameter, a.unit);
        return { label: labelShown(title), values: a.values.map((v) => v * factorOf(title)) };
      };
      // The changes name the two cells by their values; find them on the axes.
      const edges = (r.chatter_type_changes || []).map((c) => [
        nearest(rowsAxis.values, c.from[0]) * nc + nearest(columnsAxis.values, c.from[1]),
        nearest(rowsAxis.values, c.to[0]) * nc + nearest(columnsAxis.values, c.to[1]),
      ]);
      const controls = panel(plots, 'Operating window');
      const label = document.createElement('label');
      label.htmlFor = 'map-speed';
      label.textContent = `Operating speed [${shown('m/s').unit}]: cells stable at it are outlined `;
      const input = document.createElement('input');
      const operating = Number.isFinite(rolling) ? inShown(rolling, 'm/s') : null;
      Object.assign(input, { id: 'map-speed', type: 'number', step: 'any', min: '0', value: operating != null ? String(operating) : '' });
      const key = document.createElement('p');
      key.className = 'help';
      key.id = 'map-key';
      key.textContent = `Each cell: its critical speed [${shown('m/s').unit}] (also its colour) and the chatter type of the mode that goes unstable as a symbol; `
        + 'a cell without a critical speed: its letter. '
        + 'Thick black outline: stable at the operating speed (below the critical speed). Dashed red edge: the chatter type changes between the two cells.';
      const legend = document.createElement('ul');
      legend.id = 'map-legend';
      legend.className = 'legend';
      legend.setAttribute('aria-label', 'Symbols of the map');
      for (const [symbol, meaning] of [...Object.values(chatterTypes).map((t) => [t.symbol, `${t.name} chatter`]),
        ...Object.entries(classes).map(([status, c]) => [c.symbol, { stable_in_range: 'stable over the whole search range', unstable_at_lower_bound: 'unstable already at the lowest speed searched', no_steady_state: 'no steady bite' }[status]])]) {
        const item = document.createElement('li');
        const mark = document.createElement('span');
        mark.className = 'symbol';
        mark.textContent = symbol;
        item.append(mark, ` ${meaning}`);
        item.dataset.symbol = symbol;
        legend.append(item);
      }
      controls.append(label, input, key, legend);
      const map = drawHeatmap(plots, {
        id: 'map', title: `Critical speed over ${fieldName(doc, rowsAxis.parameter).toLowerCase()} and ${fieldName(doc, columnsAxis.parameter).toLowerCase()}${response.partial ? ' (running: the finished cells)' : ''}`,
        description: key.textContent,
        rows: axis(rowsAxis), columns: axis(columnsAxis),
        cells, valueLabel: labelShown('critical speed [m/s]'), speed: operating, edges,
        stableAt: (c, v) => c.cell.status === 'stable_in_range' || (c.value != null && v < c.value),
      });
      input.addEventListener('input', () => { const v = Number(input.value); map.model.setSpeed(input.value !== '' && Number.isFinite(v) ? v : null); });
      input.setAttribute('aria-describedby', key.id);
      const done = r.cells.filter(Boolean);
      const found = done.map((c) => c.critical_speed_m_per_s).filter((v) => v !== null);
      const details = document.createElement('details');
      const summary = document.createElement('summary');
      summary.textContent = 'The cells as a table';
      details.append(summary, numberTable('Critical speed per cell', [axisLabel(doc, rowsAxis.parameter, rowsAxis.unit), axisLabel(doc, columnsAxis.parameter, columnsAxis.unit), 'status', 'critical speed [m/s]', 'frequency [Hz]', 'chatter type'],
        done.map((c) => [c.values[0], c.values[1], c.status, c.critical_speed_m_per_s, c.frequency_Hz, chatterName(c.chatter_type)])));
      panel(plots, 'Cells').append(details);
      return [
        row('rows', `${fieldName(doc, rowsAxis.parameter)} (${rowsAxis.values.length})`), row('columns', `${fieldName(doc, columnsAxis.parameter)} (${nc})`),
        row('cells done', `${done.length} of ${r.cells.length}`),
        row('lowest critical speed', found.length ? min(found) : null, 'm/s'), row('highest critical speed', found.length ? max(found) : null, 'm/s'),
        row('chatter type changes', response.partial ? null : (r.chatter_type_changes || []).length),
      ];
    },
  },
  tandem: {
    render(response, plots) {
      const r = response.result;
      const s = r.stability || {};
      const c = r.critical_speeds;
      const root = s.rightmost_root;
      const focus = criticalRoot(r);
      millRow(plots, response, focus);
      criticalSpeeds(plots, response);
      marginFactors(plots, s);
      speedSweep(plots, response);
      participation(plots, focus);
      timeSeries(plots, r.time_series, r.steady_state.stands.length);
      return [
        row("mill speed (the last stand's roll speed)", response.tandem.speed_m_per_s, 'm/s'),
        row('stands', r.steady_state.stands.length),
        row('steady state', r.steady_state.status === 'ok' ? 'ok' : `${r.steady_state.status}: ${r.steady_state.message}`),
        ['stable at the mill speed', yesNo(s.stable), ''],
        row('rightmost root: growth rate', root && root.growth_rate_per_s, '1/s'),
        row('rightmost root: frequency', root && root.frequency_Hz, 'Hz'),
        row('headline critical speed', c ? c.critical_speed_m_per_s : 'not asked', c ? 'm/s' : ''),
        ['headline crossing', c ? (c.headline ? crossingNames[c.headline] : `none inside the model's range`) : 'not asked', ''],
        ['its chatter type (its band)', c && c.headline ? `${chatterName(c[c.headline].chatter_type)} (${chatterName(c[c.headline].band)})` : '—', ''],
        ['moving stand', focus && focus.root.moving_stand != null ? `stand ${focus.root.moving_stand}` : '—', ''],
        ['feeding stand', focus && focus.root.feeding_stand != null ? `stand ${focus.root.feeding_stand}` : '—', ''],
        ['stands marked for', focus ? focus.what : '—', ''],
        row('regenerative margin ρ', s.regenerative_margin, '-'),
        row('mass flow per width', r.steady_state.mass_flow_m2_per_s, 'm²/s'),
      ];
    },
  },
  speed_limit: {
    render(response, plots, { doc } = {}) {
      const r = response.result;
      speedLimitAxis(plots, response);
      const u = r.uncertainty;
      const changes = r.what_to_change && r.what_to_change.changes ? r.what_to_change.changes.filter((c) => c.speed_gain_m_per_s != null) : [];
      return [
        ['answer', r.summary, ''],
        row('operating speed', r.operating_speed_m_per_s, 'm/s'), row('advised speed', r.advised_speed_m_per_s, 'm/s'),
        ['binding limit', r.binding_limit ? limitNames[r.binding_limit] || r.binding_limit : '—', ''],
        row('permitted from', r.window_min_m_per_s, 'm/s'),
        ['the lower end set by', r.binding_min ? limitNames[r.binding_min] || r.binding_min : '—', ''],
        row('critical speed', r.critical_speed && r.critical_speed.critical_speed_m_per_s, 'm/s'),
        row('its standard deviation', u ? u.standard_deviation_m_per_s : null, 'm/s'),
        row('its lower bound', u ? u.lower_bound_m_per_s : null, 'm/s'),
        ...changes.slice(0, 3).map((c) => row(`to run faster: ${c.direction} ${fieldName(doc, c.field).toLowerCase()} (${c.field}) by ${fmt(c.step)}${fieldInfo(doc, c.field).unit ? ` ${fieldInfo(doc, c.field).unit}` : ''}`, c.speed_gain_m_per_s, 'm/s')),
      ];
    },
  },
  tandem_speed_limit: {
    render(response, plots, { doc } = {}) {
      const r = response.result;
      speedLimitAxis(plots, response, true);
      const c = r.critical_speeds;
      const u = r.uncertainty;
      const named = (kind, stand) => (kind ? `${limitNames[kind] || kind}${stand != null ? ` of stand ${stand}` : ''}` : '—');
      // what to change (docs/model.md §13.6): fields of the tandem document, the largest gain first
      const changes = r.what_to_change && r.what_to_change.changes ? r.what_to_change.changes.filter((x) => x.speed_gain_m_per_s != null) : [];
      const basis = { headline: "the mill's headline critical speed", none_in_range: 'no crossing in the range', outside_model_range: "crossings only outside the model's range", unstable_at_lowest_speed: 'unstable at the lowest speed', not_checked: 'not checked' };
      return [
        ['answer', r.summary, ''],
        row("mill speed (the last stand's roll speed)", r.operating_speed_m_per_s, 'm/s'), row('advised mill speed', r.advised_speed_m_per_s, 'm/s'),
        ['binding limit', named(r.binding_limit, r.binding_stand), ''],
        row('permitted from', r.window_min_m_per_s, 'm/s'),
        ['the lower end set by', named(r.binding_min, r.binding_min_stand), ''],
        ['chatter limit from', basis[r.chatter_basis] || r.chatter_basis, ''],
        row('headline critical speed', c ? c.critical_speed_m_per_s : null, 'm/s'),
        ['headline crossing', c && c.headline ? crossingNames[c.headline] : '—', ''],
        // under the stands' posteriors (docs/model.md §13.7): σ, the bound the limit is taken at
        row('its standard deviation', u ? u.standard_deviation_m_per_s : null, 'm/s'),
        row('its lower bound', u ? u.lower_bound_m_per_s : null, 'm/s'),
        ...(u && u.sampled ? [row(`its standard deviation over ${u.sampled.samples} seeded draws`, u.sampled.standard_deviation_m_per_s, 'm/s')] : []),
        ...changes.slice(0, 3).map((x) => {
          const { name, unit } = millField(doc, x.field);
          return row(`to run faster: ${x.direction} ${name.toLowerCase()} (${x.field}) by ${fmt(x.step)}${unit ? ` ${unit}` : ''}`, x.speed_gain_m_per_s, 'm/s');
        }),
      ];
    },
  },
  batch: {
    job: true,
    render(response, plots) {
      const r = response.result;
      batchTable(plots, r);
      const margins = r.items.map((i) => (i.headline ? i.headline.speed_margin_m_per_s : null)).filter((v) => typeof v === 'number');
      return [
        row('analysis of every coil', r.analysis), row('coils', r.items_total), row('answered', r.succeeded), row('with a problem', r.failed),
        row('smallest speed margin', margins.length ? min(margins) : null, 'm/s'),
        row('coils above their advised speed', margins.filter((m) => m < 0).length),
      ];
    },
  },
  calibrate: {
    job: true,
    render(response, plots, { doc } = {}) {
      const r = response.result;
      const observations = r.observations || [];
      const quantities = [...new Set(observations.map((o) => o.quantity))];
      const apply = document.createElement('button');
      apply.type = 'button';
      apply.id = 'use-calibrated';
      apply.className = 'no-print';
      apply.textContent = 'Use the calibrated scenario in the editor';
      apply.addEventListener('click', () => plots.dispatchEvent(new CustomEvent('use-scenario', { bubbles: true, detail: r.calibrated_scenario })));
      const fitted = panel(plots, 'Fitted parameters');
      fitted.append(numberTable('Fitted scenario fields (standard errors from the posterior covariance)',
        ['field', 'unit', 'start', 'fitted value', 'standard error', 'min', 'max', 'at bound'],
        r.parameters.map((p) => [fieldName(doc, p.field), p.unit === '1' ? '-' : unitText(p.unit), p.start, p.value, p.standard_error, p.min, p.max, p.at_bound || 'no'])), apply);
      // Each fitted field's pointer, for experts (the row's tooltip).
      [...fitted.querySelector('tbody').rows].forEach((tr, i) => { tr.title = r.parameters[i].field; tr.dataset.field = r.parameters[i].field; });
      if (Array.isArray(r.correlation) && r.correlation.length > 1) {
        fitted.append(numberTable('Correlation of the fitted values', ['', ...r.parameters.map((p) => fieldName(doc, p.field))],
          r.correlation.map((line, i) => [fieldName(doc, r.parameters[i].field), ...line])));
      }
      const warnings = panel(plots, `Warnings (${(r.warnings || []).length})`);
      const list = document.createElement('ul');
      list.id = 'calibration-warnings';
      for (const w of r.warnings || []) {
        const item = document.createElement('li');
        item.textContent = `${w.code}: ${w.fields.map((f) => fieldName(doc, f)).join(', ')} — ${w.detail}`;
        list.append(item);
      }
      if (!(r.warnings || []).length) list.append(Object.assign(document.createElement('li'), { textContent: 'none' }));
      warnings.append(list);
      quantities.forEach((quantity) => {
        const named = quantityLabel(quantity, doc);
        const mine = observations.map((o, i) => ({ o, n: i + 1 })).filter(({ o }) => o.quantity === quantity);
        addPlot(plots, {
          id: `calibration-${quantity}`, title: `${named.replace(/ \[.*\]$/, '')}: observed ± standard uncertainty and fitted`, small: true, pointLegend: true,
          description: 'error bars: one standard uncertainty of the observation', x: 'observation number', y: /\]$/.test(named) ? named : `${named} [-]`,
          xTicks: { stepSize: 1, precision: 0 },
          plugins: [errorBars],
          data: { datasets: [
            // Chart.js draws higher `order` first: the fitted cross lies on the observed circle.
            { label: 'observed', data: mine.map(({ o, n }) => ({ x: n, y: o.value, yError: o.standard_uncertainty })), errorBars: true, order: 2,
              showLine: false, pointRadius: 5, pointStyle: 'circle', borderColor: color(0), backgroundColor: 'rgba(31,95,168,0.25)', borderWidth: 2 },
            { label: 'fitted', data: mine.map(({ o, n }) => ({ x: n, y: o.predicted })), showLine: false, pointRadius: 8, pointStyle: 'crossRot', order: 1,
              borderWidth: 3, borderColor: color(1), backgroundColor: color(1) },
          ] },
        });
      });
      addPlot(plots, {
        id: 'calibration-residuals', type: 'bar', title: 'Normalised residuals (fitted − observed) / uncertainty',
        description: 'most lie within ±2 when the fit and the uncertainties are right', x: 'observation', y: 'normalised residual [-]',
        yTicks: { callback: (v) => fmt(v, 3) },
        data: { labels: observations.map((o, i) => `${i + 1} ${o.quantity}`), datasets: [{ label: 'normalised residual', data: observations.map((o) => o.normalised_residual), backgroundColor: color(0) }] },
      });
      return [
        row('status', r.status), row('iterations', r.iterations), row('model evaluations', r.evaluations),
        row('χ² of the observations', r.chi_squared_observations), row('χ² of the priors', r.chi_squared_priors),
        row('degrees of freedom', r.degrees_of_freedom),
        row('χ² per degree of freedom', r.degrees_of_freedom > 0 ? (r.chi_squared_observations + r.chi_squared_priors) / r.degrees_of_freedom : null),
        row('reciprocal condition', r.reciprocal_condition), row('warnings', (r.warnings || []).length),
      ];
    },
  },
};

// An analysis the page offers without a view of its own: the scalar members of its result.
export const plainView = {
  render(response) {
    const rows = Object.entries(response.result || {}).filter(([, v]) => v === null || typeof v !== 'object').map(([k, v]) => row(k, v));
    return rows.length ? rows : [['result', 'no view on this page: see the JSON download', '']];
  },
};
export const viewOf = (name) => (Object.hasOwn(views, name) ? views[name] : plainView);
export { fmt };
