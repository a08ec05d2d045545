// Forms generated from the served OpenAPI document: every scenario field (its group, name,
// unit, description, bounds and default) and every option of an analysis comes from the
// schema, so a field added to the service appears here without touching the page. A field is
// named by its title (the field table's name column: "Lubricant viscosity"), its JSON pointer
// kept in the label's tooltip for those who type requests.
import { setUnitsShown, shown, unitText } from './charts.js';

const fieldId = (pointer) => 'f' + pointer.replace(/[^A-Za-z0-9]+/g, '-');

export function resolve(doc, schema) {
  while (schema && schema.$ref) {
    schema = schema.$ref.replace(/^#\//, '').split('/').reduce((node, key) => node[key], doc);
  }
  return schema || {};
}

const isObject = (schema) => schema.properties !== undefined;
// An array's items are objects when their schema is one, or is a composition of one (a stand's
// limits: allOf [StandLimits]; a stand's posterior: anyOf [Posterior, null]).
const itemsAreObjects = (doc, items) => {
  const schema = resolve(doc, items);
  return isObject(schema) || [...(schema.allOf || []), ...(schema.anyOf || []), ...(schema.oneOf || [])].some((s) => isObject(resolve(doc, s)));
};
const types = (schema) => [].concat(schema.type || []);

// The served document's objects come with their members sorted by name (the service's JSON
// objects are ordered maps), which puts `friction` before `strip`. The field table's own order
// (strip, rolls, lubricant, ... — the order a process engineer reads a stand in) survives in
// `required`, an array: members follow it, any others keep the document's order after them.
export function orderedProperties(schema) {
  const properties = schema.properties || {};
  const first = (schema.required || []).filter((name) => Object.hasOwn(properties, name));
  const rest = Object.keys(properties).filter((name) => !first.includes(name));
  return [...first, ...rest].map((name) => [name, properties[name]]);
}

// The leaf schema of a field of a document component (Scenario, or Tandem for a mill's field)
// at `pointer` ({} when it has none). A list's element (/exit_thickness_mm/1) is its list's.
function leafSchema(doc, pointer, component) {
  let schema = resolve(doc, doc.components.schemas[component]);
  for (const key of pointer.split('/').slice(1)) {
    if (/^\d+$/.test(key) && schema.items) {  // a list of objects: its element; of numbers: the list
      const item = resolve(doc, schema.items);
      if (item.properties) schema = item;
      continue;
    }
    schema = resolve(doc, (schema.properties || {})[key]);
  }
  return schema || {};
}
// The x-unit of a scenario field from the served document ('' when dimensionless or unknown).
export function unitOf(doc, pointer) {
  const unit = leafSchema(doc, pointer, 'Scenario')['x-unit'];
  return unit && unit !== '1' ? unit : '';
}
// A field as a label names it: { title, unit (as printed, the API's: a plot converts it to the
// units shown; '' when none), pointer } — its title from the document (the pointer when it has none).
export function fieldInfo(doc, pointer, component = 'Scenario') {
  const schema = doc ? leafSchema(doc, pointer, component) : {};
  const code = schema['x-unit'] || (schema.items && resolve(doc, schema.items)['x-unit']) || '';
  return { title: schema.title || pointer, unit: unitText(code), pointer };
}
// A calibration's measured quantity as a label names it: its title and unit from the document
// ('roll_force_kN' → 'Roll force [kN]': the quantity table's x-enum-descriptions and x-units),
// else from its name ('roll force [kN]': the unit is in the quantity's name, docs/model.md §11).
export function quantityLabel(quantity, doc) {
  const options = doc && resolve(doc, doc.components.schemas.CalibrateOptions || {});
  const observations = options && options.properties && resolve(doc, options.properties.observations || {});
  const item = observations && observations.items && resolve(doc, observations.items);
  const schema = item && item.properties && item.properties.quantity;
  const i = schema && Array.isArray(schema.enum) ? schema.enum.indexOf(quantity) : -1;
  if (i >= 0 && Array.isArray(schema['x-enum-descriptions'])) {
    const unit = unitText((schema['x-units'] || [])[i]);
    return `${schema['x-enum-descriptions'][i]}${unit ? ` [${unit}]` : ''}`;
  }
  const [, name, unit] = /^(.*?)(?:_(kN_m|kN|m_per_s|Hz))?$/.exec(quantity);
  const printed = unit ? unit.replace('_per_', '/').replace('kN_m', 'kN·m') : '';
  return `${name.replace(/_/g, ' ')}${printed ? ` [${printed}]` : ''}`;
}
// "Lubricant viscosity [Pa·s]": the field's title and its unit.
export function fieldLabel(doc, pointer, component = 'Scenario') {
  const { title, unit } = fieldInfo(doc, pointer, component);
  return unit ? `${title} [${unit}]` : title;
}

function el(tag, attributes = {}, text) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes)) {
    if (value !== undefined && value !== null && value !== false) node.setAttribute(key, value === true ? '' : value);
  }
  if (text !== undefined) node.textContent = text;
  return node;
}

// A number in few characters and never rounded: the shortest text that reads back as it, in
// exponent form when small or large (1e-6, not 0.000001 cut to "0.00000" by a narrow input).
export function numberText(x) {
  if (typeof x !== 'number' || !Number.isFinite(x)) return String(x);
  return x !== 0 && (Math.abs(x) < 1e-3 || Math.abs(x) >= 1e6) ? x.toExponential().replace('e+', 'e') : String(x);
}

// Plant units on the inputs: in plant units a speed is typed in m/min and a viscosity in mPa·s
// (charts.js `shown`); the input shows the SI value converted and reads what is typed back into
// SI as the API converts its plant keys (docs/http-api.md "Plant units": a power of ten shifts
// the number's shortest decimal form, ÷ 60 is one correctly rounded division). The requests and
// the link stay in the API's units; an untouched input gives back its SI value as it was.
function shiftDecimal(x, places) {
  const [mantissa, exponent = '0'] = String(x).split('e');
  return Number(`${mantissa}e${Number(exponent) + places}`);
}
const inShownUnit = (si, factor) => (factor === 1 ? si : factor === 1000 ? shiftDecimal(si, 3) : Number((si * factor).toPrecision(15)));
const fromShownUnit = (value, factor) => (factor === 1 ? value : factor === 1000 ? shiftDecimal(value, -3) : value / factor);
const factorOfInput = (input) => (input.dataset.unit ? shown(input.dataset.unit).factor : 1);
// A value in `unit` (as printed) in the units shown, converted as the inputs convert it.
export const valueShown = (si, unit) => (typeof si === 'number' && unit ? inShownUnit(si, shown(unit).factor) : si);

function boundText(schema) {
  const low = schema.minimum ?? schema.exclusiveMinimum;
  const high = schema.maximum ?? schema.exclusiveMaximum;
  if (low === undefined && high === undefined) return '';
  return `${schema.exclusiveMinimum !== undefined ? '(' : '['}${low !== undefined ? numberText(low) : '−∞'}, ${high !== undefined ? numberText(high) : '∞'}${schema.exclusiveMaximum !== undefined ? ')' : ']'}`;
}

// One input for a leaf of the schema; `optional`: the field may stay empty (the service's
// default applies), as the options do.
function leafInput(doc, schema, pointer, optional) {
  const id = fieldId(pointer);
  let input;
  if (schema.enum) {
    input = el('select', { id });
    if (optional) input.append(el('option', { value: '' }, '(default)'));
    // A list of scenario fields (a sweep's parameter): each named by its title and unit.
    for (const value of schema.enum) {
      const named = typeof value === 'string' && value.startsWith('/') && fieldInfo(doc, value).title !== value;
      input.append(el('option', { value: String(value), title: named ? value : undefined }, named ? fieldLabel(doc, value) : String(value)));
    }
    input.dataset.kind = schema.enum.every((v) => typeof v === 'number') ? 'number' : 'text';
  } else if (types(schema).includes('boolean')) {
    if (optional) {
      input = el('select', { id });
      for (const [value, text] of [['', '(default)'], ['true', 'yes'], ['false', 'no']]) {
        input.append(el('option', { value }, text));
      }
    } else {
      input = el('input', { id, type: 'checkbox' });
    }
    input.dataset.kind = 'boolean';
  } else if (types(schema).includes('array') && itemsAreObjects(doc, schema.items)) {
    // A list of objects (calibration observations, map axes, a mill's stands): edited as JSON.
    input = el('textarea', { id, rows: 4, spellcheck: 'false', placeholder: 'JSON array, e.g. [{ … }]' });
    input.dataset.kind = 'json';
  } else if (types(schema).includes('array')) {
    input = el('input', { id, type: 'text', inputmode: 'decimal', placeholder: 'comma-separated numbers' });
    input.dataset.kind = 'array';
  } else if (types(schema).includes('number') || types(schema).includes('integer')) {
    input = el('input', {
      id, type: 'number', step: types(schema).includes('integer') ? '1' : 'any',
      min: schema.minimum ?? schema.exclusiveMinimum, max: schema.maximum ?? schema.exclusiveMaximum,
    });
    input.dataset.kind = 'number';
  } else {
    input = el('input', { id, type: 'text' });
    input.dataset.kind = 'text';
  }
  input.dataset.pointer = pointer;
  if (optional && schema.default !== undefined && input.tagName === 'INPUT') {
    input.placeholder = `default ${Array.isArray(schema.default) ? schema.default.map(numberText).join(', ') : numberText(schema.default)}`;
  }
  // A number in a unit the page may show in plant units: its SI bounds and default kept, shown
  // in the unit of the moment (showInputUnit).
  const unit = unitText(schema['x-unit']);
  if (input.dataset.kind === 'number' && input.tagName === 'INPUT' && unit) {
    input.dataset.unit = unit;
    input.siSchema = schema;
    input.siOptional = optional;
  }
  return input;
}

// An input's unit, bounds and default in the units shown (the label's unit, the placeholder,
// the browser's min and max, the bound in the tooltip).
function showInputUnit(input) {
  if (!input.dataset.unit) return;
  const factor = factorOfInput(input);
  const schema = input.siSchema;
  const convert = (v) => (typeof v === 'number' ? inShownUnit(v, factor) : v);
  const low = schema.minimum ?? schema.exclusiveMinimum;
  const high = schema.maximum ?? schema.exclusiveMaximum;
  if (low !== undefined) input.min = String(convert(low)); else input.removeAttribute('min');
  if (high !== undefined) input.max = String(convert(high)); else input.removeAttribute('max');
  if (input.siOptional && schema.default !== undefined) input.placeholder = `default ${numberText(convert(schema.default))}`;
  const unit = shown(input.dataset.unit).unit;
  const bound = boundText({ ...schema, minimum: convert(schema.minimum), exclusiveMinimum: convert(schema.exclusiveMinimum), maximum: convert(schema.maximum), exclusiveMaximum: convert(schema.exclusiveMaximum) });
  if (bound) input.title = `allowed ${bound} ${unit}`;
  if (input.unitLabel) input.unitLabel.textContent = ` [${unit}]`;
}

// Shows every input under `root` in `mode`'s units ('si' or 'plant'), their values unchanged.
export function switchInputUnits(root, mode) {
  const converted = [...root.querySelectorAll('input[data-unit]')];
  const values = converted.map((input) => readInput(input));
  setUnitsShown(mode);
  converted.forEach((input, i) => { writeInput(input, values[i]); showInputUnit(input); });
}

// `name`: what the label says when the schema has no title (an option's member name).
function field(doc, schema, name, pointer, optional) {
  const wrapper = el('div', { class: 'field' });
  const input = leafInput(doc, schema, pointer, optional);
  const unit = unitText(schema['x-unit'] || (schema.items && schema.items['x-unit']));
  const label = el('label', { for: input.id });
  label.append(el('span', { class: 'name' }, schema.title || name));
  if (unit) {
    input.unitLabel = el('span', { class: 'unit' }, ` [${unit}]`);
    label.append(input.unitLabel);
  }
  // The field's pointer in the request (without the form's /scenario or /tandem), for experts.
  if (schema.title) label.title = pointer.replace(/^\/(scenario|tandem)(?=\/)/, '');
  const help = el('p', { class: 'help', id: `${input.id}-help` },
    (schema.description || '').replace(/ null restores the default\.$/, ''));
  input.setAttribute('aria-describedby', help.id);
  if (optional) label.title = help.textContent;
  const bound = boundText(schema);
  if (bound) input.title = `allowed ${bound}${unit && unit !== '1' ? ' ' + unit : ''}`;
  showInputUnit(input);
  const error = el('p', { class: 'field-error', id: `${input.id}-error`, hidden: true });
  if (input.dataset.kind === 'json') wrapper.classList.add('wide');
  if (input.dataset.kind === 'array') wrapper.classList.add('list');  // room for its default's numbers
  const spec = input.dataset.kind === 'json' && rowsSpec(doc, resolve(doc, schema.items || {}), schema);
  if (spec) {  // rows of inputs over the JSON, which folds away under them
    const editor = new RowsEditor(input, doc, spec);
    const json = el('details', { class: 'as-json' });
    json.append(el('summary', {}, 'as JSON (to paste a list)'), input, error);
    wrapper.append(label, editor.element, json, help);
    return wrapper;
  }
  wrapper.append(label, input, error, help);
  return wrapper;
}

// ---- lists of objects as rows of inputs -------------------------------------------------------
// A map's two axes, a fit's parameters and its observations are lists of objects: edited as a
// table, one row per item, each cell an input for one member (a field picked by its title, its
// unit beside it). The JSON textarea under the rows stays the value the options form reads,
// writes and links, and experts may paste a list into it: the rows are rebuilt from it and
// write it back on every input, keeping the members they do not show (a parameter's prior, an
// observation's other conditions). A problem's pointer into the list lands at its cell.

// Rows over a JSON textarea outside the options form (a stored stand's calibration): `list`, the
// list's schema; the textarea folds away under the rows. False when the list has no rows.
export function attachRows(textarea, doc, list) {
  list = resolve(doc, list);
  const spec = rowsSpec(doc, resolve(doc, list.items || {}), list);
  if (!spec) return false;
  const editor = new RowsEditor(textarea, doc, spec);
  const json = el('details', { class: 'as-json' });
  textarea.replaceWith(editor.element);
  editor.element.after(json);
  json.append(el('summary', {}, 'as JSON (to paste a list)'), textarea);
  return true;
}

// A leaf schema's bounds ({ min, max }, undefined where open).
function boundsOf(doc, pointer) {
  const schema = leafSchema(doc, pointer, 'Scenario');
  return { min: schema.minimum ?? schema.exclusiveMinimum, max: schema.maximum ?? schema.exclusiveMaximum };
}
const quantityUnit = (quantity, doc) => (/\[(.*)\]$/.exec(quantityLabel(quantity || '', doc)) || [])[1] || '';

// What rows a list's items get: columns (a member's path in the item, its header, its kind),
// the unit of a row's numbers, how a row is named; null for a list edited as JSON only.
function rowsSpec(doc, items, list) {
  const p = items.properties || {};
  const fields = (values) => values.map((v) => [v, fieldLabel(doc, v)]);
  const fieldUnit = (item) => (item.parameter || item.field ? fieldInfo(doc, item.parameter || item.field).unit : '');
  if (p.parameter && Array.isArray(p.parameter.enum) && p.range) {  // a map's axes
    const fixed = list.minItems && list.minItems === list.maxItems ? list.minItems : 0;
    return {
      what: 'axis', fixed, rowName: (i) => (fixed === 2 ? ['rows', 'columns'][i] : `axis ${i + 1}`), unit: fieldUnit,
      columns: [
        { path: ['parameter'], header: 'field', kind: 'choice', choices: fields(p.parameter.enum), row: true },
        { path: ['range', 'from'], header: 'from', kind: 'number' },
        { path: ['range', 'to'], header: 'to', kind: 'number' },
        { path: ['range', 'count'], header: 'count', kind: 'integer', min: 2 },
        { path: ['values'], header: 'or values', kind: 'numbers', placeholder: 'a, b, c' },
      ],
      // One of values and range: values typed replace the range.
      finish(item) { if (item.values) delete item.range; },
    };
  }
  if (p.field && Array.isArray(p.field.enum) && (p.min || p.max)) {  // a fit's parameters
    return {
      what: 'parameter', rowName: (i) => `parameter ${i + 1}`, rowHead: (i) => String(i + 1), unit: fieldUnit,
      columns: [
        { path: ['field'], header: 'field', kind: 'choice', choices: fields(p.field.enum), row: true },
        { path: ['min'], header: 'from (lower bound)', kind: 'number', placeholder: (item) => boundsOf(doc, item.field || '').min },
        { path: ['max'], header: 'to (upper bound)', kind: 'number', placeholder: (item) => boundsOf(doc, item.field || '').max },
      ],
    };
  }
  if (p.quantity && Array.isArray(p.quantity.enum) && p.standard_uncertainty) {  // a fit's observations
    return {
      what: 'observation', rowName: (i) => `observation ${i + 1}`, rowHead: (i) => String(i + 1), unit: (item) => quantityUnit(item.quantity, doc),
      columns: [
        { path: ['quantity'], header: 'quantity', kind: 'choice', choices: p.quantity.enum.map((q) => [q, quantityLabel(q, doc)]), row: true },
        { path: ['value'], header: 'measured', kind: 'number' },
        { path: ['standard_uncertainty'], header: 'uncertainty (1σ)', kind: 'number', min: 0 },
        // The condition a coil is usually measured at; other conditions stay in the JSON.
        ...(p.scenario ? [{ path: ['scenario', 'rolls', 'speed_m_per_s'], header: `at ${fieldLabel(doc, '/rolls/speed_m_per_s').toLowerCase()}`, kind: 'number', placeholder: () => 'scenario' }] : []),
        ...(p.mode ? [{ path: ['mode', 'near_frequency_Hz'], header: 'mode near [Hz]', kind: 'number', placeholder: () => 'modal only' }] : []),
      ],
      // A mode given near a frequency is not also given by its index.
      finish(item) { if (item.mode && item.mode.near_frequency_Hz !== undefined) delete item.mode.index; },
    };
  }
  return null;
}

const cellText = (v) => (typeof v === 'number' ? String(v) : v === undefined || v === null ? '' : String(v));
function getPath(item, path) { return path.reduce((node, key) => (node == null ? undefined : node[key]), item); }
function setPath(item, path, value) {
  let node = item;
  for (const key of path.slice(0, -1)) node = node[key] = node[key] && typeof node[key] === 'object' ? node[key] : {};
  node[path[path.length - 1]] = value;
}
// Removes the member at path, and the objects on the way it leaves empty.
function deletePath(item, path) {
  const parents = [item];
  for (const key of path.slice(0, -1)) { const next = parents.at(-1)[key]; if (!next || typeof next !== 'object') return; parents.push(next); }
  delete parents.at(-1)[path.at(-1)];
  for (let k = parents.length - 1; k > 0; k--) if (!Object.keys(parents[k]).length) delete parents[k - 1][path[k - 1]];
}

class RowsEditor {
  constructor(textarea, doc, spec) {
    this.textarea = textarea;
    this.spec = spec;
    this.items = [];
    this.element = el('div', { class: 'rows-editor' });
    this.body = el('tbody');
    const table = el('table', { class: 'rows' });
    const head = el('tr');
    head.append(el('th', { scope: 'col' }, spec.what), ...spec.columns.map((c) => el('th', { scope: 'col' }, c.header)));
    head.insertBefore(el('th', { scope: 'col' }, 'unit'), head.children[2]);
    if (!spec.fixed) head.append(el('th', { scope: 'col' }, 'remove'));
    table.append(el('thead'), this.body);
    table.tHead.append(head);
    // Focusable, so a keyboard can scroll it when it is wider than its panel.
    const scroll = el('div', { class: 'table-scroll', tabindex: '0', role: 'region', 'aria-label': `${spec.what}s` });
    scroll.append(table);
    this.element.append(scroll);
    if (!spec.fixed) {
      const add = el('button', { type: 'button', class: 'add-row', id: `${textarea.id}-add` }, `Add ${/^[aeiou]/.test(spec.what) ? 'an' : 'a'} ${spec.what}`);
      add.addEventListener('click', () => { this.items.push({}); this.render(); this.body.lastElementChild.querySelector('select, input').focus(); });
      this.element.append(add);
    }
    textarea.rowsEditor = this;
    textarea.addEventListener('input', () => this.refresh());
    this.refresh();
  }

  // The rows anew from the JSON (a list that does not parse leaves them as they are).
  refresh() {
    let items = [];
    const text = this.textarea.value.trim();
    if (text) {
      try { items = JSON.parse(text); } catch { return; }
      if (!Array.isArray(items)) return;
    }
    this.items = items.map((item) => (item && typeof item === 'object' ? item : {}));
    this.render();
  }

  // The rows of the items held (a row just added is empty until typed into).
  render() {
    const count = Math.max(this.items.length, this.spec.fixed || 0);
    this.body.replaceChildren(...Array.from({ length: count }, (_, i) => this.row(i, this.items[i] || {})));
  }

  row(i, item) {
    const { spec } = this;
    const pointer = `${this.textarea.dataset.pointer || ''}/${i}`;
    const tr = el('tr');
    tr.append(el('th', { scope: 'row' }, spec.rowHead ? spec.rowHead(i) : spec.rowName(i)));
    const unit = el('td', { class: 'unit' }, spec.unit(item) || '-');
    spec.columns.forEach((column, k) => {
      const id = `${this.textarea.id}-${i}-${column.path.join('-')}`;
      const value = getPath(item, column.path);
      let input;
      if (column.kind === 'choice') {
        input = el('select', { id });
        input.append(el('option', { value: '' }, `(choose a ${column.header})`));
        for (const [v, text] of column.choices) input.append(el('option', { value: v, title: v.startsWith('/') ? v : undefined }, text));
        input.value = value ?? '';
      } else {
        const placeholder = typeof column.placeholder === 'function' ? column.placeholder(item) : column.placeholder;
        input = el('input', {
          id, type: column.kind === 'numbers' ? 'text' : 'number', inputmode: 'decimal', step: column.kind === 'integer' ? '1' : 'any',
          min: column.min, placeholder: placeholder === undefined ? undefined : typeof placeholder === 'number' ? numberText(placeholder) : placeholder,
        });
        input.value = Array.isArray(value) ? value.join(', ') : cellText(value);
      }
      const cellUnit = column.header.startsWith('mode') || column.header.startsWith('at ') || column.kind === 'integer' || k === 0 ? '' : spec.unit(item);
      input.setAttribute('aria-label', `${spec.rowName(i)}: ${column.header}${cellUnit ? ` [${cellUnit}]` : ''}`);
      // Where a problem's pointer lands: this member, and for the first cell the row itself.
      input.dataset.errorAt = `${pointer}/${column.path.join('/')}${column.row ? ` ${pointer}` : ''}`;
      const help = el('p', { class: 'help visually-hidden', id: `${id}-help` }, `${spec.what} ${i + 1}, ${column.header}`);
      input.setAttribute('aria-describedby', help.id);
      input.addEventListener('input', () => { this.read(i, tr); if (k === 0) unit.textContent = spec.unit(this.items[i]) || '-'; });
      input.addEventListener('change', () => { if (k === 0) this.refreshRow(i); });
      const cell = el('td');
      cell.append(input, el('p', { class: 'field-error', id: `${id}-error`, hidden: true }), help);
      tr.append(cell);
      if (k === 0) tr.append(unit);
    });
    if (!spec.fixed) {
      const remove = el('button', { type: 'button', class: 'remove-row', 'aria-label': `Remove ${spec.rowName(i)}` }, 'Remove');
      remove.addEventListener('click', () => { this.items.splice(i, 1); this.write(); this.render(); });
      const cell = el('td');
      cell.append(remove);
      tr.append(cell);
    }
    return tr;
  }

  // A row's new field or quantity: its placeholders (the field's bounds) follow it.
  refreshRow(i) {
    const fresh = this.row(i, this.items[i] || {});
    this.body.children[i].replaceWith(fresh);
    fresh.querySelector('select').focus();
  }

  // Row i's inputs into its item (members not shown kept), then the JSON.
  read(i, tr) {
    const item = structuredClone(this.items[i] || {});
    this.spec.columns.forEach((column, k) => {
      const input = tr.querySelectorAll('td > select, td > input')[k];
      const raw = input.value.trim();
      if (raw === '') { deletePath(item, column.path); return; }
      let value = raw;
      if (column.kind === 'number' || column.kind === 'integer') value = Number.isNaN(Number(raw)) ? raw : Number(raw);
      if (column.kind === 'numbers') value = raw.split(/[\s,;]+/).filter(Boolean).map((v) => (Number.isNaN(Number(v)) ? v : Number(v)));
      setPath(item, column.path, value);
    });
    if (this.spec.finish) this.spec.finish(item);
    while (this.items.length <= i) this.items.push({});
    this.items[i] = item;
    this.write();
  }

  // The list into the JSON: nothing when every row is empty (the option is then left out).
  write() {
    const items = this.items.slice(0, Math.max(this.items.length, this.spec.fixed || 0)).map((item) => item || {});
    this.textarea.value = items.some((item) => Object.keys(item).length)
      ? `[\n${items.map((item) => ' ' + JSON.stringify(item)).join(',\n')}\n]` : '';
  }
}

// Builds the fieldsets and inputs of an object schema into `container`.
export function buildFields(container, doc, schema, prefix, { optional = false, depth = 0 } = {}) {
  schema = resolve(doc, schema);
  for (const [name, raw] of orderedProperties(schema)) {
    const child = resolve(doc, raw);
    const pointer = `${prefix}/${name}`;
    if (isObject(child)) {
      const group = depth === 0 && !optional ? el('details', { class: 'group', open: true }) : el('fieldset', { class: 'group' });
      const title = depth === 0 && !optional ? el('summary', {}, name.replace(/_/g, ' ')) : el('legend', {}, name.replace(/_/g, ' '));
      group.append(title);
      if (child.description && optional) group.append(el('p', { class: 'help' }, child.description));
      buildFields(group, doc, child, pointer, { optional, depth: depth + 1 });
      container.append(group);
    } else {
      container.append(field(doc, child, name, pointer, optional));
    }
  }
}

function readInput(input) {
  const raw = input.type === 'checkbox' ? input.checked : input.value.trim();
  if (input.type === 'checkbox') return raw;
  if (raw === '') return undefined;
  switch (input.dataset.kind) {
    case 'number': {
      const n = Number(raw);
      if (Number.isNaN(n)) return raw;
      // In plant units: the value written there, untouched, is its SI value as it was.
      if (input.dataset.si !== undefined && raw === input.dataset.shownText) return Number(input.dataset.si);
      return fromShownUnit(n, factorOfInput(input));
    }
    case 'boolean': return raw === 'true';
    case 'json': try { return JSON.parse(raw); } catch { return raw; }  // the service names what is wrong
    case 'array': return raw.split(/[\s,;]+/).filter(Boolean).map((v) => (Number.isNaN(Number(v)) ? v : Number(v)));
    default: return raw;
  }
}

function writeInput(input, value) {
  if (input.type === 'checkbox') input.checked = Boolean(value);
  else if (value === undefined || value === null) input.value = '';
  else if (input.dataset.kind === 'json') input.value = Array.isArray(value) ? `[\n${value.map((item) => ' ' + JSON.stringify(item)).join(',\n')}\n]` : JSON.stringify(value);
  else if (Array.isArray(value)) input.value = value.join(', ');
  else input.value = String(typeof value === 'number' ? inShownUnit(value, factorOfInput(input)) : value);
  if (input.dataset.unit && typeof value === 'number' && factorOfInput(input) !== 1) {
    input.dataset.si = String(value);
    input.dataset.shownText = input.value;
  } else {
    delete input.dataset.si;
    delete input.dataset.shownText;
  }
  if (input.rowsEditor) input.rowsEditor.refresh();
}

const getAt = (object, pointer) => pointer.split('/').slice(1).reduce((node, key) => (node == null ? undefined : node[key]), object);
// A member on the way that does not exist yet is an object, or an array before an index.
function setAt(object, pointer, value) {
  const keys = pointer.split('/').slice(1);
  let node = object;
  keys.slice(0, -1).forEach((key, i) => { node = node[key] ??= (/^\d+$/.test(keys[i + 1]) ? [] : {}); });
  node[keys[keys.length - 1]] = value;
}

// RFC 7396: members of the patch replace the target's, null removes, objects merge.
export function mergePatch(target, patch) {
  if (patch === null || typeof patch !== 'object' || Array.isArray(patch)) return patch;
  const out = target && typeof target === 'object' && !Array.isArray(target) ? target : {};
  for (const [key, value] of Object.entries(patch)) {
    if (value === null) delete out[key];
    else out[key] = mergePatch(out[key], value);
  }
  return out;
}

const inputs = (form) => [...form.querySelectorAll('[data-pointer]')];
const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);

// The scenario form: values are always filled in, the patch holds those that differ from the
// base (the default scenario, or a stored one the requests then name as `base`).
export class ScenarioForm {
  constructor(form, doc, base) {
    this.form = form;
    this.base = base;
    buildFields(form, doc, doc.components.schemas.Scenario, '/scenario');
    this.apply({});
  }
  // A new base keeps what the inputs show; only the patch (the differences) changes.
  setBase(base) { this.base = base; this.markChanges(); }
  apply(patch) { this.applyFull(mergePatch(structuredClone(this.base), patch || {})); }
  // Shows a complete scenario (fields it lacks keep the base's value).
  applyFull(scenario) {
    for (const input of inputs(this.form)) {
      const pointer = input.dataset.pointer.replace(/^\/scenario/, '');
      const value = getAt(scenario, pointer);
      writeInput(input, value !== undefined ? value : getAt(this.base, pointer));
    }
    this.markChanges();
  }
  patch() {
    const patch = {};
    for (const input of inputs(this.form)) {
      const pointer = input.dataset.pointer.replace(/^\/scenario/, '');
      const value = readInput(input);
      if (value !== undefined && !same(value, getAt(this.base, pointer))) setAt(patch, pointer, value);
    }
    return patch;
  }
  // Every field that differs from the base, as [pointer, base value, value].
  changes() {
    return inputs(this.form)
      .map((input) => [input.dataset.pointer.replace(/^\/scenario/, ''), input])
      .map(([pointer, input]) => [pointer, getAt(this.base, pointer), readInput(input)])
      .filter(([, base, value]) => value !== undefined && !same(base, value));
  }
  markChanges() {
    const changed = new Set(this.changes().map(([pointer]) => `/scenario${pointer}`));
    for (const input of inputs(this.form)) input.closest('.field').classList.toggle('changed', changed.has(input.dataset.pointer));
  }
}

// The options of one analysis: empty fields are left out, so the service's defaults apply.
export class OptionsForm {
  constructor(form, doc, schema) {
    this.form = form;
    form.replaceChildren();
    buildFields(form, doc, schema, '/options', { optional: true });
  }
  apply(options) {
    for (const input of inputs(this.form)) writeInput(input, getAt(options || {}, input.dataset.pointer.replace(/^\/options/, '')));
  }
  options() {
    const options = {};
    for (const input of inputs(this.form)) {
      const value = readInput(input);
      if (value !== undefined) setAt(options, input.dataset.pointer.replace(/^\/options/, ''), value);
    }
    return options;
  }
}

// Places each violation of a problem at the input its JSON pointer names (or the nearest
// enclosing one, e.g. /options/values/3 at the values input); returns those without an input.
export function showFieldErrors(root, errors) {
  clearFieldErrors(root);
  const unplaced = [];
  let first = null;
  for (const error of errors || []) {
    let pointer = error.pointer || '';
    let input = null;
    // A row's cell (data-error-at) before the list's JSON that holds it (data-pointer).
    const at = (p) => root.querySelector(`[data-error-at~="${CSS.escape(p)}"]`) || root.querySelector(`[data-pointer="${CSS.escape(p)}"]`);
    while (pointer && !(input = at(pointer))) pointer = pointer.replace(/\/[^/]*$/, '');
    if (!input) { unplaced.push(error); continue; }
    const message = input.parentElement.querySelector('.field-error');
    const bound = error.bound ? ` Allowed: ${error.bound}${error.unit && error.unit !== '1' ? ' ' + error.unit : ''}.` : '';
    message.textContent = `${error.detail}${bound}`;
    message.hidden = false;
    input.setAttribute('aria-invalid', 'true');
    input.setAttribute('aria-describedby', `${message.id} ${input.id}-help`);
    const details = input.closest('details');
    if (details) details.open = true;
    first ??= input;
  }
  if (first) {
    first.focus();
    first.parentElement.querySelector('.field-error').scrollIntoView({ block: 'center' });
  }
  return unplaced;
}

export function clearFieldErrors(root) {
  for (const message of root.querySelectorAll('.field-error')) { message.hidden = true; message.textContent = ''; }
  for (const input of root.querySelectorAll('[aria-invalid]')) {
    input.removeAttribute('aria-invalid');
    input.setAttribute('aria-describedby', `${input.id}-help`);
  }
}

// ---- the tandem mill --------------------------------------------------------------------------

const isPlain = (value) => value !== null && typeof value === 'object' && !Array.isArray(value);

// A merge patch (RFC 7396) that takes `base` to `value`: objects member by member, arrays and
// numbers whole; undefined when they are the same. `nulls`: members of base that value lacks
// become null (removed); without it they are left alone (an echo that omits what it does not own).
export function diffPatch(base, value, { nulls = true } = {}) {
  if (isPlain(base) && isPlain(value)) {
    const out = {};
    for (const [key, child] of Object.entries(value)) {
      const d = Object.hasOwn(base, key) ? diffPatch(base[key], child, { nulls }) : child;
      if (d !== undefined) out[key] = d;
    }
    if (nulls) for (const key of Object.keys(base)) if (!Object.hasOwn(value, key)) out[key] = null;
    return Object.keys(out).length ? out : undefined;
  }
  return same(base, value) ? undefined : value;
}

// The default of a schema from its `default`s (objects member by member).
export function schemaDefaults(doc, schema) {
  schema = resolve(doc, schema);
  if (schema.default !== undefined) return structuredClone(schema.default);
  if (!isObject(schema)) return undefined;
  const out = {};
  for (const [name, child] of orderedProperties(schema)) {
    const value = schemaDefaults(doc, child);
    if (value !== undefined) out[name] = value;
  }
  return out;
}

// Leaves of a merge patch as [pointer, value] (arrays whole).
export function patchLeaves(patch, prefix = '', out = []) {
  for (const [key, value] of Object.entries(patch || {})) {
    if (isPlain(value) && Object.keys(value).length) patchLeaves(value, `${prefix}/${key}`, out);
    else out.push([`${prefix}/${key}`, value]);
  }
  return out;
}

const millLists = ['exit_thickness_mm', 'spans', 'stand_defaults', 'stands'];  // edited by the rows below
const listShown = (value) => (Array.isArray(value) ? value.map((v) => (isPlain(v) ? JSON.stringify(v) : v)).join(', ') : isPlain(value) ? JSON.stringify(value) : value);

// The tandem mill (components.schemas.Tandem): the number of stands, the mill's own numbers
// generated from the schema, one row per stand (its exit thickness, its scenario patch) and one
// per interstand span (length, tension), each input at the JSON pointer a 422 names
// (/tandem/exit_thickness_mm/1, /tandem/spans/tension_MPa/0, /tandem/stands/2/...). The request
// carries the merge patch onto the default mill; the default comes from the schema's defaults.
export class MillForm {
  constructor(form, doc, scenarioDefaults) {
    this.form = form;
    this.doc = doc;
    this.scenarioDefaults = scenarioDefaults || {};
    const schema = resolve(doc, doc.components.schemas.Tandem);
    this.schema = schema;
    const defaults = schemaDefaults(doc, schema);
    const count = (defaults.exit_thickness_mm || []).length || 1;
    defaults.stand_defaults ??= {};
    defaults.stands ??= Array.from({ length: count }, () => ({}));
    this.base = defaults;
    this.defaults = structuredClone(defaults);
    const stands = resolve(doc, schema.properties.stands);
    this.minStands = stands.minItems ?? 1;
    this.maxStands = stands.maxItems ?? 6;

    const subset = (names) => ({ properties: Object.fromEntries(names.map((n) => [n, schema.properties[n]])), required: names });
    const own = orderedProperties(schema).map(([name]) => name).filter((name) => !millLists.includes(name));
    const first = own.filter((name) => !isObject(resolve(doc, schema.properties[name])) && name !== 'mode');
    const countField = field(doc, {
      type: 'integer', minimum: this.minStands, maximum: this.maxStands,
      description: `How many stands the mill has (${this.minStands} to ${this.maxStands}); the rows below follow it.`,
    }, 'number of stands', '/tandem/stands', false);
    this.count = countField.querySelector('input');
    form.replaceChildren(countField);
    buildFields(form, doc, subset(first), '/tandem');
    this.rows = el('div', { class: 'mill-rows' });
    form.append(this.rows);
    buildFields(form, doc, subset(own.filter((name) => !first.includes(name))), '/tandem');
    const shared = el('details', { class: 'group' });
    shared.append(el('summary', {}, 'shared stand settings'));
    const sharedField = field(doc, { type: 'string', description: resolve(doc, schema.properties.stand_defaults).description }, 'stand defaults (scenario patch, JSON)', '/tandem/stand_defaults', false);
    this.jsonInput(sharedField);
    shared.append(sharedField);
    form.append(shared);
    this.count.addEventListener('input', () => {
      const n = Number(this.count.value);
      if (Number.isInteger(n) && n >= this.minStands && n <= this.maxStands && n !== this.stands) this.setCount(n);
    });
    this.apply({});
  }

  jsonInput(wrapper) {
    const input = wrapper.querySelector('input');
    const area = el('textarea', { id: input.id, rows: 2, spellcheck: 'false', placeholder: '{}', 'aria-describedby': input.getAttribute('aria-describedby') });
    area.dataset.pointer = input.dataset.pointer;
    area.dataset.kind = 'json';
    input.replaceWith(area);
    wrapper.classList.add('wide');
    return area;
  }

  // One fieldset per stand and per span for a mill of `document`'s stands.
  buildRows(document) {
    const n = document.exit_thickness_mm.length;
    this.stands = n;
    this.count.value = String(n);
    const doc = this.doc;
    const properties = this.schema.properties;
    const thickness = resolve(doc, properties.exit_thickness_mm).items;
    const spans = resolve(doc, properties.spans).properties;
    const standsGroup = el('details', { class: 'group', open: true });
    standsGroup.append(el('summary', {}, 'pass schedule, stand by stand'));
    for (let i = 0; i < n; i++) {
      const set = el('fieldset', { class: 'group mill-row-set' });
      set.append(el('legend', {}, `stand ${i + 1}`));
      set.append(field(doc, { ...thickness, description: `Strip thickness leaving stand ${i + 1}${i ? ` (it enters from stand ${i})` : ' (it enters at the mill\'s entry thickness)'}.` }, resolve(doc, properties.exit_thickness_mm).title || 'exit thickness', `/tandem/exit_thickness_mm/${i}`, false));
      const patch = field(doc, { type: 'string', description: `Stand ${i + 1}'s own scenario patch (rolls, lubricant, friction, structure …), after the shared stand settings; {} takes them as they are.` }, 'stand settings (scenario patch, JSON)', `/tandem/stands/${i}`, false);
      this.jsonInput(patch);
      set.append(patch);
      standsGroup.append(set);
    }
    const spansGroup = el('details', { class: 'group', open: true });
    spansGroup.append(el('summary', {}, 'interstand spans'));
    for (let j = 0; j + 1 < n; j++) {
      const set = el('fieldset', { class: 'group mill-row-set' });
      set.append(el('legend', {}, `span from stand ${j + 1} to stand ${j + 2}`));
      set.append(field(doc, { ...resolve(doc, spans.length_m).items, description: `Length of the strip between stand ${j + 1} and stand ${j + 2}.` }, resolve(doc, spans.length_m).title || 'length', `/tandem/spans/length_m/${j}`, false));
      set.append(field(doc, { ...resolve(doc, spans.tension_MPa).items, description: `Tension set point between stand ${j + 1} and stand ${j + 2}, as a stress.` }, resolve(doc, spans.tension_MPa).title || 'tension', `/tandem/spans/tension_MPa/${j}`, false));
      spansGroup.append(set);
    }
    if (n < 2) spansGroup.append(el('p', { class: 'help' }, 'A mill of one stand has no interstand span.'));
    this.rows.replaceChildren(standsGroup, spansGroup);
  }

  // A new number of stands: the rows kept, new ones from the default mill (or the last row's,
  // a thinner exit).
  setCount(n) {
    const full = this.full();
    const resize = (list, length, fill) => Array.from({ length }, (_, i) => (i < list.length && list[i] != null ? list[i] : fill(i)));
    const defaults = this.base;
    const thickness = [];
    for (let i = 0; i < n; i++) {
      const kept = full.exit_thickness_mm[i];
      if (kept != null) { thickness.push(kept); continue; }
      const before = i ? thickness[i - 1] : full.entry_thickness_mm;
      const fromDefault = defaults.exit_thickness_mm[i];
      thickness.push(fromDefault !== undefined && !(fromDefault >= before) ? fromDefault : Number((before * 0.88).toPrecision(3)));
    }
    full.exit_thickness_mm = thickness;
    for (const key of ['length_m', 'tension_MPa']) full.spans[key] = resize(full.spans[key], Math.max(0, n - 1), (i) => defaults.spans[key][i] ?? full.spans[key].at(-1) ?? defaults.spans[key][0]);
    full.stands = resize(full.stands, n, () => ({}));
    this.applyFull(full, { patches: true });
  }

  // The complete mill the inputs show.
  full() {
    const n = this.stands;
    const out = structuredClone(this.base);
    out.exit_thickness_mm = Array(n).fill(null);
    out.spans.length_m = Array(Math.max(0, n - 1)).fill(null);
    out.spans.tension_MPa = Array(Math.max(0, n - 1)).fill(null);
    out.stands = Array.from({ length: n }, () => ({}));
    for (const input of inputs(this.form)) {
      const pointer = input.dataset.pointer.replace(/^\/tandem/, '');
      if (pointer === '/stands') continue;
      const value = readInput(input);
      if (value === undefined) continue;  // an empty input: the default (a list's element: null, which the service names)
      setAt(out, pointer, value);
    }
    return out;
  }

  // A new base (a stored mill as GET /v1/mills/{name} gives it, resolved; none: the default
  // mill) keeps what the inputs show; only the patch (the differences) changes. Its stands are
  // held as the inputs show them, their differences from the default scenario.
  setBase(mill) {
    if (!mill) { this.base = structuredClone(this.defaults); this.markChanges(); return; }
    const base = mergePatch(structuredClone(this.defaults), structuredClone(mill));
    base.stand_defaults ??= {};
    base.stands = (base.stands || []).map((stand) => diffPatch(this.scenarioDefaults, stand, { nulls: false }) || {});
    this.base = base;
    this.markChanges();
  }

  patch() { return diffPatch(this.base, this.full()) || {}; }
  apply(patch) { this.applyFull(mergePatch(structuredClone(this.base), structuredClone(patch || {})), { patches: true }); }
  // Shows a complete mill: the answer's echo (each stand a complete scenario, shown as its
  // difference from the default scenario) or, with `patches`, one whose stands are patches.
  applyFull(tandem, { patches = false } = {}) {
    const full = mergePatch(structuredClone(this.base), structuredClone(tandem || {}));
    const n = Math.min(this.maxStands, Math.max(this.minStands, (full.exit_thickness_mm || []).length));
    if (!Array.isArray(full.stands) || full.stands.length !== n) full.stands = Array.from({ length: n }, (_, i) => (full.stands || [])[i] || {});
    if (!patches) full.stands = full.stands.map((stand) => diffPatch(this.scenarioDefaults, stand, { nulls: false }) || {});
    this.buildRows({ exit_thickness_mm: Array(n) });
    for (const input of inputs(this.form)) {
      const pointer = input.dataset.pointer.replace(/^\/tandem/, '');
      if (pointer === '/stands') continue;
      writeInput(input, getAt(full, pointer));
    }
    this.markChanges();
  }
  // Every field that differs from the default mill, as [pointer, default, value].
  changes() {
    return patchLeaves(this.patch()).map(([pointer, value]) => [pointer, listShown(getAt(this.base, pointer)), listShown(value)]);
  }
  markChanges() {
    const changed = this.changes().map(([pointer]) => `/tandem${pointer}`);
    for (const input of inputs(this.form)) {
      const pointer = input.dataset.pointer;
      const mine = changed.some((c) => c === pointer || pointer.startsWith(`${c}/`) || (pointer === '/tandem/stands' && c.startsWith('/tandem/stands')));
      input.closest('.field').classList.toggle('changed', mine && readInput(input) !== undefined && !same(readInput(input), getAt(this.base, pointer.replace(/^\/tandem/, ''))));
    }
  }
}
