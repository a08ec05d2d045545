// Downloads of a result (JSON as the service answered it, CSV as the service writes it) and the
// printable report: headline, plots, the full scenario and the rollgap version.

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
  const mill = response.tandem !== undefined;
  scenarioBox.replaceChildren(table(mill ? 'The full mill used' : 'The full scenario used', flatten((mill ? response.tandem : response.scenario) || {}), ['field', 'value']),
    table('The options used', flatten(response.options || {}), ['option', 'value']));
}
