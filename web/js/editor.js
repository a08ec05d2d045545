// Forms generated from the served OpenAPI document: every scenario field (its group, name,
// unit, description, bounds and default) and every option of an analysis comes from the
// schema, so a field added to the service appears here without touching the page.

const fieldId = (pointer) => 'f' + pointer.replace(/[^A-Za-z0-9]+/g, '-');

export function resolve(doc, schema) {
  while (schema && schema.$ref) {
    schema = schema.$ref.replace(/^#\//, '').split('/').reduce((node, key) => node[key], doc);
  }
  return schema || {};
}

const isObject = (schema) => schema.properties !== undefined;
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

// The x-unit of a scenario field from the served document ('' when dimensionless or unknown).
export function unitOf(doc, pointer) {
  let schema = resolve(doc, doc.components.schemas.Scenario);
  for (const key of pointer.split('/').slice(1)) schema = resolve(doc, (schema.properties || {})[key]);
  const unit = schema && schema['x-unit'];
  return unit && unit !== '1' ? unit : '';
}

function el(tag, attributes = {}, text) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes)) {
    if (value !== undefined && value !== null && value !== false) node.setAttribute(key, value === true ? '' : value);
  }
  if (text !== undefined) node.textContent = text;
  return node;
}

function boundText(schema) {
  const low = schema.minimum ?? schema.exclusiveMinimum;
  const high = schema.maximum ?? schema.exclusiveMaximum;
  if (low === undefined && high === undefined) return '';
  return `${schema.exclusiveMinimum !== undefined ? '(' : '['}${low ?? '−∞'}, ${high ?? '∞'}${schema.exclusiveMaximum !== undefined ? ')' : ']'}`;
}

// One input for a leaf of the schema; `optional`: the field may stay empty (the service's
// default applies), as the options do.
function leafInput(doc, schema, pointer, optional) {
  const id = fieldId(pointer);
  let input;
  if (schema.enum) {
    input = el('select', { id });
    if (optional) input.append(el('option', { value: '' }, '(default)'));
    for (const value of schema.enum) input.append(el('option', { value: String(value) }, String(value)));
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
  } else if (types(schema).includes('array') && isObject(resolve(doc, schema.items))) {
    // A list of objects (calibration observations, map axes): edited as JSON.
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
  if (optional && schema.default !== undefined && input.tagName === 'INPUT') input.placeholder = `default ${schema.default}`;
  return input;
}

function field(doc, schema, name, pointer, optional) {
  const wrapper = el('div', { class: 'field' });
  const input = leafInput(doc, schema, pointer, optional);
  const unit = schema['x-unit'] || (schema.items && schema.items['x-unit']);
  const label = el('label', { for: input.id });
  label.append(el('span', { class: 'name' }, name));
  if (unit && unit !== '1') label.append(el('span', { class: 'unit' }, ` [${unit}]`));
  const help = el('p', { class: 'help', id: `${input.id}-help` },
    (schema.description || '').replace(/ null restores the default\.$/, ''));
  input.setAttribute('aria-describedby', help.id);
  if (optional) label.title = help.textContent;
  const bound = boundText(schema);
  if (bound) input.title = `allowed ${bound}${unit && unit !== '1' ? ' ' + unit : ''}`;
  const error = el('p', { class: 'field-error', id: `${input.id}-error`, hidden: true });
  if (input.dataset.kind === 'json') wrapper.classList.add('wide');
  wrapper.append(label, input, error, help);
  return wrapper;
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
    case 'number': { const n = Number(raw); return Number.isNaN(n) ? raw : n; }
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
  else input.value = String(value);
}

const getAt = (object, pointer) => pointer.split('/').slice(1).reduce((node, key) => (node == null ? undefined : node[key]), object);
function setAt(object, pointer, value) {
  const keys = pointer.split('/').slice(1);
  let node = object;
  for (const key of keys.slice(0, -1)) node = node[key] ??= {};
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
    while (pointer && !(input = root.querySelector(`[data-pointer="${CSS.escape(pointer)}"]`))) pointer = pointer.replace(/\/[^/]*$/, '');
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
