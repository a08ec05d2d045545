// Downloads of a result (JSON as the service answered it, CSV as the service writes it) and the
// printable report: headline, plots, the full scenario and the rollgap version.
import { inShown, shown } from './charts.js';

// `data`: a string or a Blob, saved as it is.
function save(name, type, data) {
  const url = URL.createObjectURL(new Blob([data], { type }));
  const link = document.createElement('a');
  link.href = url;
  link.download = name;
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

export function downloadJson(response) {
  save(`rollgap-${response.analysis}.json`, 'application/json', JSON.stringify(response, null, 2));
}
// The service's CSV of a result (Accept: text/csv on its route or its job), unchanged.
export function downloadCsv(analysis, blob) {
  save(`rollgap-${analysis}.csv`, 'text/csv', blob);
}

function flatten(object, prefix = '', out = []) {
  for (const [key, value] of Object.entries(object)) {
    if (value && typeof value === 'object' && !Array.isArray(value)) flatten(value, `${prefix}/${key}`, out);
    else if (Array.isArray(value) && value.some((v) => v && typeof v === 'object')) flatten({ ...value }, `${prefix}/${key}`, out);  // a mill's stands
    else out.push([`${prefix}/${key}`, Array.isArray(value) ? value.join(', ') : String(value)]);
  }
  return out;
}

export function table(caption, rows, header) {
  const t = document.createElement('table');
  const c = document.createElement('caption');
  c.textContent = caption;
  t.append(c);
  if (header) {
    const tr = t.createTHead().insertRow();
    for (const h of header) { const th = document.createElement('th'); th.scope = 'col'; th.textContent = h; tr.append(th); }
  }
  const body = t.createTBody();
  for (const r of rows) {
    const tr = body.insertRow();
    r.forEach((cell, i) => {
      const node = document.createElement(i === 0 ? 'th' : 'td');
      if (i === 0) node.scope = 'row';
      node.textContent = cell;
      tr.append(node);
    });
  }
  return t;
}

// Fills the report's head (title, version, time, link) and the full scenario (or mill).
// One sentence a process engineer can put in a shift report, from the answer's own numbers.
const number = (value, digits = 3) => Number(value.toPrecision(digits)).toString();
// A speed in the units shown: "15 m/s", or "900 m/min" in plant units.
const speedText = (value) => `${number(inShown(value, 'm/s'))} ${shown('m/s').unit}`;
export function conclusion(response, stand) {
  const r = response.result || {};
  const speed = response.scenario && response.scenario.rolls && response.scenario.rolls.speed_m_per_s;
  const critical = (r.critical_speed && r.critical_speed.critical_speed_m_per_s)
    ?? (r.stability && r.stability.critical_speed && r.stability.critical_speed.critical_speed_m_per_s);
  if (response.analysis === 'speed_limit' && r.advised_speed_m_per_s != null) {
    return `${stand}: advised speed ${speedText(r.advised_speed_m_per_s)}${r.binding_limit ? ` (binding: ${r.binding_limit.replace(/_/g, ' ')})` : ''}${r.operating_speed_m_per_s != null ? `; it runs at ${speedText(r.operating_speed_m_per_s)}` : ''}.`;
  }
  if (speed != null && critical != null) {
    return `${stand} runs at ${speedText(speed)}, ${Math.round((100 * speed) / critical)} % of its ${speedText(critical)} chatter limit.`;
  }
  if (speed != null && r.critical_speed && critical == null) {
    return `${stand} runs at ${speedText(speed)}; no chatter limit was found in the searched speeds.`;
  }
  if (speed != null && r.force_kN != null) return `${stand} at ${speedText(speed)}: roll force ${number(r.force_kN, 4)} kN.`;
  return '';
}

// The report's head: a title and an author the engineer types (kept in this browser), the stand,
// the date, the one-line conclusion, the link.
// `name(pointer)`: a field's title and unit ("Lubricant viscosity [Pa·s]"); the tables keep the pointer beside it.
export function fillReport(head, scenarioBox, response, { label, version, link, changes, base = 'default scenario', name = (pointer) => pointer }) {
  head.replaceChildren();
  const stand = base === 'default scenario' ? 'The default stand' : base.replace(/^stored scenario /, 'Stand ');
  const editable = (id, text, placeholder, key) => {
    const input = document.createElement('input');
    input.id = id;
    input.type = 'text';
    input.className = 'report-editable';
    input.placeholder = placeholder;
    input.setAttribute('aria-label', placeholder);
    input.value = localStorage.getItem(key) ?? text;
    input.addEventListener('input', () => localStorage.setItem(key, input.value));
    return input;
  };
  const h = document.createElement('h2');
  h.append(editable('report-title', `rollgap report: ${label}`, 'report title', 'rollgap-report-title'));
  const meta = document.createElement('p');
  meta.id = 'report-meta';
  meta.append(`${stand} · ${new Date().toISOString().slice(0, 10)} · by `,
    editable('report-author', '', 'author', 'rollgap-report-author'),
    ` · rollgap ${version} · ${new Date().toISOString().replace('T', ' ').slice(11, 19)} UTC`);
  const line = document.createElement('p');
  line.id = 'report-conclusion';
  line.className = 'report-conclusion';
  line.textContent = conclusion(response, stand);
  const a = document.createElement('a');
  a.href = link;
  a.textContent = 'link to this view';
  a.className = 'no-print';
  head.append(h, meta, line, a);
  if (changes.length) head.append(table(`Fields changed from the ${base}`, changes.map(([p, b, v]) => [name(p), String(b), String(v), p]), ['field', 'base', 'value', 'pointer']));
  const mill = response.tandem !== undefined;
  scenarioBox.replaceChildren(table(mill ? 'The full mill used' : 'The full scenario used', flatten((mill ? response.tandem : response.scenario) || {}).map(([p, v]) => [name(p), v, p]), ['field', 'value', 'pointer']),
    table('The options used', flatten(response.options || {}), ['option', 'value']));
}
