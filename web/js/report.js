// Downloads of a result (JSON as the service answered it, CSV of its tabular part) and the
// printable report: headline, plots, the full scenario and the rollgap version.

function save(name, type, text) {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const link = document.createElement('a');
  link.href = url;
  link.download = name;
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

const csvCell = (value) => {
  const text = value === null || value === undefined ? '' : String(value);
  return /[",\n]/.test(text) ? `"${text.replace(/"/g, '""')}"` : text;
};
export const toCsv = (rows) => rows.map((r) => r.map(csvCell).join(',')).join('\n') + '\n';

export function downloadJson(response) {
  save(`rollgap-${response.analysis}.json`, 'application/json', JSON.stringify(response, null, 2));
}
export function downloadCsv(response, rows) {
  save(`rollgap-${response.analysis}.csv`, 'text/csv', toCsv(rows));
}

function flatten(object, prefix = '', out = []) {
  for (const [key, value] of Object.entries(object)) {
    if (value && typeof value === 'object' && !Array.isArray(value)) flatten(value, `${prefix}/${key}`, out);
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

// Fills the report's head (title, version, time, link) and the full scenario.
export function fillReport(head, scenarioBox, response, { label, version, link, changes, base = 'default scenario' }) {
  head.replaceChildren();
  const h = document.createElement('h2');
  h.textContent = `rollgap report: ${label}`;
  const meta = document.createElement('p');
  meta.textContent = `rollgap ${version} · ${new Date().toISOString().replace('T', ' ').slice(0, 19)} UTC`;
  const a = document.createElement('a');
  a.href = link;
  a.textContent = 'link to this view';
  a.className = 'no-print';
  head.append(h, meta, a);
  if (changes.length) head.append(table(`Fields changed from the ${base}`, changes.map(([p, b, v]) => [p, String(b), String(v)]), ['field', 'base', 'value']));
  scenarioBox.replaceChildren(table('The full scenario used', flatten(response.scenario), ['field', 'value']),
    table('The options used', flatten(response.options || {}), ['option', 'value']));
}
