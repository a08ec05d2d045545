// The workbench in a real browser: Debian's chromium driven by playwright-core, against a real
// `rollgap serve` on loopback that this script starts and stops. What the page plots is
// compared with a direct call of the API; screenshots of each view go to SCREENSHOT_DIR.
//
//   node workbench.test.mjs <rollgap binary> <screenshot dir>
// Env: ROLLGAP_NODE_TOOLS (npm packages: playwright-core, axe-core), CHROMIUM (/usr/bin/chromium).
import { spawn } from 'node:child_process';
import { mkdirSync, mkdtempSync, readFileSync, rmSync, statSync } from 'node:fs';
import os from 'node:os';
import { createRequire } from 'node:module';
import path from 'node:path';

const [binary, screenshots] = process.argv.slice(2);
const tools = process.env.ROLLGAP_NODE_TOOLS || '/var/cache/rollgap/node-tools';
const require = createRequire(path.join(tools, 'package.json'));
const { chromium } = require('playwright-core');
const axeSource = readFileSync(require.resolve('axe-core/axe.min.js'), 'utf8');
rmSync(screenshots, { recursive: true, force: true });  // only this run's views
mkdirSync(screenshots, { recursive: true });

// ---- the server ------------------------------------------------------------------------------
// A job store of its own (SQLite in a fresh data directory), so no earlier run's jobs or stored
// scenarios show.
const dataDir = mkdtempSync(path.join(os.tmpdir(), 'rollgap-browser-'));
function startServer() {
  const child = spawn(binary, ['serve', '--port', '0', '--bind', '127.0.0.1', '--workers', '2', '--data-dir', dataDir], { stdio: ['ignore', 'ignore', 'pipe'] });
  return new Promise((resolve, reject) => {
    let log = '';
    const timer = setTimeout(() => { child.kill('SIGKILL'); reject(new Error(`server did not start:\n${log}`)); }, 30000);
    child.stderr.on('data', (chunk) => {
      log += chunk;
      const match = /msg=listening\b.*?\saddress=127\.0\.0\.1:(\d+)/.exec(log); // not admin_address
      if (match) { clearTimeout(timer); child.stderr.removeAllListeners('data'); child.stderr.resume(); resolve({ child, base: `http://127.0.0.1:${match[1]}` }); }
    });
    child.on('exit', (code) => { clearTimeout(timer); reject(new Error(`server exited ${code}:\n${log}`)); });
  });
}
function stopServer(child) {
  return new Promise((resolve) => {
    if (child.exitCode !== null) return resolve();
    const timer = setTimeout(() => child.kill('SIGKILL'), 15000);
    child.on('exit', () => { clearTimeout(timer); resolve(); });
    child.kill('SIGTERM');
  });
}

// ---- a tiny runner ---------------------------------------------------------------------------
const results = [];
async function test(name, body) {
  const started = Date.now();
  try {
    await body();
    results.push([name, true]);
    console.log(`ok - ${name} (${Date.now() - started} ms)`);
  } catch (error) {
    results.push([name, false]);
    await page.screenshot({ path: path.join(screenshots, `failed-${name.replace(/[^a-z0-9]+/gi, '-')}.png`), fullPage: true }).catch(() => {});
    console.log(`not ok - ${name}\n  ${String(error && error.stack || error).replace(/\n/g, '\n  ')}`);
  }
}
function check(condition, message) { if (!condition) throw new Error(message); }
function equalArrays(actual, expected, what) {
  check(actual.length === expected.length, `${what}: ${actual.length} values plotted, the API gave ${expected.length}`);
  actual.forEach((v, i) => check(Object.is(v, expected[i]) || v === expected[i], `${what}[${i}]: plotted ${v}, the API gave ${expected[i]}`));
}

// Clicks "Download CSV" and returns the file the browser saved.
async function downloadCsv(analysis) {
  check(await page.isVisible('#download-csv'), 'the CSV download is offered');
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download-csv')]);
  check(download.suggestedFilename() === `rollgap-${analysis}.csv`, `file name ${download.suggestedFilename()}`);
  return readFileSync(await download.path());
}
function equalBytes(saved, served, what) {
  check(saved.length > 0 && saved.equals(served), `${what}: the page saved ${saved.length} bytes, the service answers ${served.length}:\n${saved.toString('utf8').slice(0, 300)}\n---\n${served.toString('utf8').slice(0, 300)}`);
}

// ---- the page --------------------------------------------------------------------------------
const { child, base } = await startServer();
const post = async (route, body) => {
  const response = await fetch(base + route, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  return { status: response.status, body: await response.json() };
};
// The service's CSV of a request, byte for byte (its one CSV writer, api/csv.cpp).
const postCsv = async (route, body) => {
  const response = await fetch(base + route, { method: 'POST', headers: { 'Content-Type': 'application/json', Accept: 'text/csv' }, body: JSON.stringify(body) });
  check(response.status === 200, `${route} with Accept: text/csv answered ${response.status}`);
  return Buffer.from(await response.arrayBuffer());
};
// The service's analyses (its OpenAPI document's list, the rows of its analysis table).
const documentAnalyses = async () => (await (await fetch(base + '/openapi.json')).json())['x-rollgap-analyses'];
// launch() gives the browser a fresh, temporary profile (user-data-dir) and removes it on close.
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--no-first-run'],
});
const context = await browser.newContext({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
const consoleErrors = [];
let expected422 = 0;
let expected412 = 0;  // a save refused as stale: the page says so
function watch(page) {
  page.on('console', (message) => {
    if (message.type() !== 'error') return;
    if (/status of 422/.test(message.text()) && expected422 > 0) { expected422--; return; }
    if (/status of 412/.test(message.text()) && expected412 > 0) { expected412--; return; }
    consoleErrors.push(message.text());
  });
  page.on('pageerror', (error) => consoleErrors.push(String(error)));
  return page;
}
const page = watch(await context.newPage());
const shot = (name, target = page) => target.screenshot({ path: path.join(screenshots, `${name}.png`), fullPage: true });
const chartData = (id) => page.evaluate((canvasId) => {
  const chart = Chart.getChart(document.getElementById(canvasId));
  return chart ? { labels: chart.data.labels, datasets: chart.data.datasets.map((d) => ({ label: d.label, data: d.data })) } : null;
}, `plot-${id}`);
// The titles of a chart's axes ({ x, y, y2 }).
const axisTitles = (id, target = page) => target.evaluate((canvasId) => Object.fromEntries(Object.entries(Chart.getChart(document.getElementById(canvasId)).options.scales)
  .map(([axis, scale]) => [axis, scale.title.text])), `plot-${id}`);
// The dataset whose label starts with `prefix` (a label carrying a number, e.g. the operating speed's).
const datasetStarting = (chart, prefix) => {
  const found = chart.datasets.filter((d) => d.label.startsWith(prefix));
  check(found.length === 1, `one dataset '${prefix}…' among ${chart.datasets.map((d) => d.label).join(', ')}`);
  return found[0];
};
const dataset = (chart, label) => {
  const found = chart.datasets.find((d) => d.label === label);
  check(found, `no dataset '${label}' among ${chart.datasets.map((d) => d.label).join(', ')}`);
  return found.data;
};
const chatterNames = { third_octave: 'third-octave', fifth_octave: 'fifth-octave', other: 'other' };
const axeAudit = (target = page) => target.evaluate(async () => (await axe.run(document, { resultTypes: ['violations'] })).violations
  .filter((v) => v.impact === 'serious' || v.impact === 'critical')
  .map((v) => `${v.impact} ${v.id}: ${v.help} (${v.nodes.slice(0, 3).map((n) => n.target.join(' ')).join('; ')})`));
async function checkAxe(target = page) {
  if (!(await target.evaluate(() => typeof axe !== 'undefined'))) await target.evaluate(axeSource);
  const found = await axeAudit(target);
  check(found.length === 0, found.join('\n'));
}
// Answers the page's polls of a job with `fake(job)` (a running job with a partial result)
// until `release()`; the job itself runs on in the service.
async function holdJob(fake) {
  let held = true;
  const route = async (route) => {
    if (!held || route.request().method() !== 'GET') return route.fallback();
    const real = await (await route.fetch()).json();
    return route.fulfill({ status: 200, contentType: 'application/json', body: JSON.stringify(fake(real)) });
  };
  await page.route(/\/v1\/jobs\/[0-9a-f]{32}$/, route);
  // Released, it passes every request on (not unrouted: a poll may be in flight in it).
  return () => { held = false; };
}
const heatmap = () => page.evaluate(() => {
  const m = document.getElementById('plot-map').heatmap;
  return { axes: m.axes, rows: m.rows, columns: m.columns, values: m.values, symbols: m.symbols, texts: m.texts, legend: m.legend, edges: m.edges, stable: m.stable, speed: m.speed,
    pixels: m.values.map((_, k) => m.pixel(Math.floor(k / m.columns.length), k % m.columns.length)),
    colours: m.values.map((v) => (v === null ? null : m.colorOf(v))) };
});

// The damping chart of a stability drawn beside a pinned one (`name`): the pinned modes share
// one legend entry that names the run, this run's keep theirs; both critical speeds marked; each
// the API's (`pinnedApi`, `currentApi`: the answers' critical_speed).
async function checkPinnedDamping(name, pinnedApi, currentApi) {
  const damping = await chartData('damping');
  const theirs = damping.datasets.filter((d) => d.label === `pinned (${name}): each mode, dashed`);
  equalArrays(theirs.map((d) => d.data.map((p) => p.y).join()), pinnedApi.damping_branches.map((b) => b.damping_ratio.join()), 'the pinned modes');
  currentApi.damping_branches.forEach((b, i) => equalArrays(damping.datasets[i].data.map((p) => p.y), b.damping_ratio, `this run's mode ${i + 1}`));
  check(dataset(damping, 'critical speed — pinned')[0].x === pinnedApi.critical_speed_m_per_s, 'the pinned critical speed');
  check(dataset(damping, 'critical speed — this run')[0].x === currentApi.critical_speed_m_per_s, 'this run\'s critical speed');
}

async function runAndWait(plot) {
  await page.evaluate(() => document.getElementById('plots').replaceChildren());
  await page.click('#run');
  await page.waitForSelector(`#plot-${plot}`, { timeout: 120000 });
}

// JSON with every object's members sorted: two documents compared whatever their members' order.
const canon = (value) => JSON.stringify(value, (_, v) => (v && typeof v === 'object' && !Array.isArray(v) ? Object.fromEntries(Object.entries(v).sort(([a], [b]) => (a < b ? -1 : 1))) : v));
// Fills a list's rows (a map's axes, a fit's parameters and observations): `items`, each cell's
// value by the member's path ('range/from'); a select by its value. Adds rows where it may.
async function fillRows(list, items) {
  for (const [i, item] of items.entries()) {
    if (!(await page.$(`#${list}-${i}-${Object.keys(item)[0].replace(/\//g, '-')}`))) await page.click(`#${list}-add`);
    for (const [path, value] of Object.entries(item)) {
      const id = `#${list}-${i}-${path.replace(/\//g, '-')}`;
      if ((await page.$eval(id, (e) => e.tagName)) === 'SELECT') await page.selectOption(id, value);
      else await page.fill(id, String(value));
    }
  }
}
const listValue = (id) => page.$eval(`#${id}`, (t) => (t.value.trim() ? JSON.parse(t.value) : null));

// The JSON bodies the page POSTs to `path` while `action` runs.
async function postedDuring(path, action) {
  const sent = [];
  const listen = (request) => { if (request.method() === 'POST' && request.url() === base + path) sent.push(request.postDataJSON()); };
  page.on('request', listen);
  try {
    await action();
  } finally {
    page.off('request', listen);
  }
  return sent;
}

try {
  await test('the page is served from the binary under a strict CSP; it lists the service\'s jobs and stored scenarios', async () => {
    const asked = [];
    const listen = (request) => { if (request.method() === 'GET' && /\/v1\/(scenarios(?!\/default)|jobs(\?|$))/.test(request.url())) asked.push(request.url()); };
    page.on('request', listen);
    const response = await page.goto(base + '/');
    check(response.status() === 200, `GET / answered ${response.status()}`);
    const csp = response.headers()['content-security-policy'] || '';
    check(/default-src 'self'/.test(csp) && !/unsafe-inline|unsafe-eval/.test(csp), `CSP: ${csp}`);
    await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
    const html = await (await fetch(base + '/')).text();
    check(!/<script(?![^>]*\bsrc=)[^>]*>/i.test(html) && !/\sstyle=/i.test(html), 'the page has inline script or style');
    page.off('request', listen);
    // The OpenAPI document offers GET /v1/jobs and /v1/scenarios: the page asks both.
    check(asked.some((url) => /\/v1\/jobs(\?|$)/.test(url)), `the job list was not asked: ${asked.join(', ')}`);
    check(asked.some((url) => /\/v1\/scenarios$/.test(url)), `the stored scenarios were not asked: ${asked.join(', ')}`);
    await page.waitForFunction(() => /this service/.test(document.getElementById('jobs-title').textContent));
  });

  await test('the scenario editor has one labelled input per field of the served OpenAPI Scenario', async () => {
    const doc = await (await fetch(base + '/openapi.json')).json();
    const leaves = [];
    (function walk(schema, prefix) {
      for (const [name, child] of Object.entries(schema.properties)) {
        if (child.properties) walk(child, `${prefix}/${name}`); else leaves.push(`/scenario${prefix}/${name}`);
      }
    })(doc.components.schemas.Scenario, '');
    const inputs = await page.$$eval('#scenario-form [data-pointer]', (all) => all.map((i) => ({
      pointer: i.dataset.pointer, label: document.querySelector(`label[for="${i.id}"]`)?.textContent || '',
      help: document.getElementById(`${i.id}-help`)?.textContent || '' })));
    equalArrays(inputs.map((i) => i.pointer).sort(), leaves.sort(), 'scenario inputs');
    const reduction = inputs.find((i) => i.pointer === '/scenario/strip/reduction');
    check(reduction.help === doc.components.schemas.Scenario.properties.strip.properties.reduction.description, 'the glossary description is shown');
    const thickness = inputs.find((i) => i.pointer === '/scenario/strip/entry_thickness_mm');
    check(/\[mm\]/.test(thickness.label), `unit in the label: ${thickness.label}`);
    check(await page.inputValue('#f-scenario-strip-reduction') === '0.15', 'the default reduction is filled in');
    await shot('editor');
  });

  await test("fields are named by the document's titles and units, their pointers kept as tooltips (editor, mill editor, sweep's picker)", async () => {
    const doc = await (await fetch(base + '/openapi.json')).json();
    const leaves = [];
    (function walk(schema, prefix) {
      for (const [name, child] of Object.entries(schema.properties)) {
        if (child.properties) walk(child, `${prefix}/${name}`); else leaves.push([`${prefix}/${name}`, child]);
      }
    })(doc.components.schemas.Scenario, '');
    const labels = await page.$$eval('#scenario-form [data-pointer]', (all) => Object.fromEntries(all.map((i) => {
      const label = document.querySelector(`label[for="${i.id}"]`);
      return [i.dataset.pointer, { name: label.querySelector('.name').textContent, unit: label.querySelector('.unit')?.textContent || '', tip: label.title }];
    })));
    for (const [pointer, schema] of leaves) {
      check(schema.title, `the document names ${pointer}`);
      const shown = labels[`/scenario${pointer}`];
      check(shown.name === schema.title && shown.tip === pointer, `${pointer}: labelled ${JSON.stringify(shown)}, titled ${schema.title}`);
      check(Boolean(shown.unit) === Boolean(schema['x-unit'] && schema['x-unit'] !== '1'), `${pointer}: unit ${shown.unit}, x-unit ${schema['x-unit']}`);
    }
    // UCUM codes as a reader writes them.
    const viscosity = labels['/scenario/lubricant/viscosity_Pa_s'];
    check(`${viscosity.name}${viscosity.unit}` === 'Lubricant viscosity [Pa·s]', `viscosity: ${JSON.stringify(viscosity)}`);
    // The mill's fields by the Tandem component's titles.
    const tension = await page.$eval('label[for="f-tandem-spans-tension-MPa-0"]', (l) => l.textContent);
    check(tension === `${doc.components.schemas.Tandem.properties.spans.properties.tension_MPa.title} [MPa]`, `span tension: ${tension}`);
    // A sweep's field picker names each field; its value stays the pointer.
    await page.click('#tab-sweep');
    const options = await page.$$eval('#f-options-parameter option', (all) => all.filter((o) => o.value).map((o) => [o.value, o.textContent, o.title]));
    check(options.length > 10, `${options.length} fields to sweep`);
    for (const [pointer, text, tip] of options) {
      const schema = leaves.find(([p]) => p === pointer)[1];
      check(text.startsWith(schema.title) && tip === pointer, `${pointer} offered as ${text}`);
    }
    check(options.some(([p, text]) => p === '/lubricant/viscosity_Pa_s' && text === 'Lubricant viscosity [Pa·s]'), 'the viscosity with its unit');
    // The options by their titles too (the option table's name column), never by their keys.
    await page.click('#tab-stability');
    const optionLabels = await page.$$eval('#options-form [data-pointer]', (all) => all.map((i) => [i.dataset.pointer, document.querySelector(`label[for="${i.id}"]`).querySelector('.name').textContent]));
    const stability = doc.components.schemas.StabilityOptions.properties;
    equalArrays(optionLabels.map(([p]) => p).sort(), Object.keys(stability).map((k) => `/options/${k}`).sort(), 'one input per stability option');
    for (const [pointer, name] of optionLabels) {
      const title = stability[pointer.replace('/options/', '')].title;
      check(title && name === title && !name.includes('_'), `${pointer}: labelled ${name}, titled ${title}`);
    }
    check(optionLabels.some(([p, name]) => p === '/options/relative_tolerance' && name === 'Search tolerance'), 'relative_tolerance is the search tolerance');
    await page.click('#tab-roll_gap');
  });

  await test('every default shown in full: placeholders fit their inputs and read back as the document\'s default (1e-6, not "0.00000")', async () => {
    const doc = await (await fetch(base + '/openapi.json')).json();
    const components = doc.components.schemas;
    const resolve = (schema) => (schema && schema.$ref ? resolve(components[schema.$ref.split('/').pop()]) : schema || {});
    // Each option's numeric default, by its pointer in the form (/options/critical_speed/...).
    const defaultsOf = (schema, prefix, out = new Map()) => {
      for (const [name, child] of Object.entries(resolve(schema).properties || {})) {
        const leaf = resolve(child);
        if (typeof leaf.default === 'number') out.set(`${prefix}/${name}`, leaf.default);
        else if (leaf.properties) defaultsOf(leaf, `${prefix}/${name}`, out);
      }
      return out;
    };
    let shownCount = 0;
    let small = 0;
    try {
      for (const row of (await documentAnalyses()).filter((r) => r.on_page)) {
        await page.click(`#tab-${row.name}`);
        const schema = row.options_schema ? components[row.options_schema] : resolve(doc.paths[row.path].post.requestBody.content['application/json'].schema).properties.options;
        const defaults = defaultsOf(schema, '/options');
        const shown = await page.$$eval('#options-form input[placeholder^="default "]', (all) => all.map((input) => {
          const style = getComputedStyle(input);
          const ctx = document.createElement('canvas').getContext('2d');
          ctx.font = `${style.fontStyle} ${style.fontWeight} ${style.fontSize} ${style.fontFamily}`;
          const room = input.clientWidth - parseFloat(style.paddingLeft) - parseFloat(style.paddingRight);
          return { pointer: input.dataset.pointer, text: input.placeholder, width: ctx.measureText(input.placeholder).width, room };
        }));
        for (const s of shown) {
          check(s.width <= s.room, `${row.name} ${s.pointer}: "${s.text}" is ${Math.ceil(s.width)} px in ${Math.floor(s.room)} px`);
          if (!defaults.has(s.pointer)) continue;
          const value = Number(s.text.replace(/^default /, ''));
          check(value === defaults.get(s.pointer), `${row.name} ${s.pointer}: shows "${s.text}", the document's default is ${defaults.get(s.pointer)}`);
          shownCount++;
          if (value !== 0 && Math.abs(value) < 1e-3) small++;
        }
      }
    } finally {
      await page.click('#tab-roll_gap');
    }
    check(shownCount > 20 && small > 0, `${shownCount} numeric defaults compared, ${small} of them below 1e-3`);
  });

  await test("the analysis selector is the document's analysis list: its on_page rows, in order, labelled", async () => {
    const rows = await documentAnalyses();
    check(Array.isArray(rows) && rows.length > 0, 'the document lists the analyses (x-rollgap-analyses)');
    const tabs = await page.$$eval('#tabs [role="tab"]', (all) => all.map((t) => ({ name: t.dataset.key, id: t.id, label: t.textContent, title: t.title })));
    const shown = rows.filter((r) => r.on_page);
    equalArrays(tabs.map((t) => t.name), shown.map((r) => r.name), 'tabs');
    equalArrays(tabs.map((t) => t.id), shown.map((r) => `tab-${r.name}`), 'tab ids');
    equalArrays(tabs.map((t) => t.label), shown.map((r) => r.label), 'tab labels');
    equalArrays(tabs.map((t) => t.title), shown.map((r) => r.summary), 'tab titles');
  });

  await test("the editor's groups and fields follow the field table's order (the document's required lists)", async () => {
    const doc = await (await fetch(base + '/openapi.json')).json();
    const scenario = doc.components.schemas.Scenario;
    const groups = await page.$$eval('#scenario-form > details > summary', (all) => all.map((s) => s.textContent));
    equalArrays(groups, scenario.required.map((name) => name.replace(/_/g, ' ')), 'editor groups');
    check(groups[0] === 'strip', `the first group is ${groups[0]}`);
    const strip = await page.$$eval('#scenario-form > details:first-of-type > .field [data-pointer]', (all) => all.map((i) => i.dataset.pointer));
    equalArrays(strip, scenario.properties.strip.required.map((name) => `/scenario/strip/${name}`), 'strip fields');
  });

  const patch = { strip: { reduction: 0.2 } };
  await test('an edited field runs the roll gap; the plot is the API data; the neutral point is at the pressure peak', async () => {
    await page.fill('#f-scenario-strip-reduction', '0.2');
    const diff = await page.textContent('#diff li[data-pointer="/strip/reduction"]');
    const reduction = (await (await fetch(base + '/openapi.json')).json()).components.schemas.Scenario.properties.strip.properties.reduction;
    check(diff === `${reduction.title}: 0.15 → 0.2` && await page.getAttribute('#diff li', 'title') === '/strip/reduction', `diff list: ${diff}`);
    await runAndWait('pressure');
    const api = (await post('/v1/roll-gap', { scenario: patch })).body.result;
    const chart = await chartData('pressure');
    const pressure = dataset(chart, 'pressure [MPa]');
    equalArrays(pressure.map((p) => p.x), api.distribution.x_mm, 'x_mm');
    equalArrays(pressure.map((p) => p.y), api.distribution.pressure_MPa, 'pressure_MPa');
    equalArrays(dataset(chart, 'friction stress [MPa]').map((p) => p.y), api.distribution.friction_MPa, 'friction_MPa');
    const neutral = dataset(chart, 'neutral point');
    const peak = pressure.reduce((best, p) => (p.y > best.y ? p : best));
    check(neutral[0].x === peak.x && neutral[1].x === peak.x, `neutral marker at ${neutral[0].x} mm, pressure peaks at ${peak.x} mm`);
    const film = await chartData('film');
    equalArrays(dataset(film, 'contact ratio [-]').map((p) => p.y), api.distribution.contact_ratio, 'contact_ratio');
    const force = await page.textContent('#headline');
    check(force.includes(String(Number(api.force_kN.toPrecision(4)))), `headline force ${api.force_kN} in: ${force}`);
    await shot('roll-gap');
  });

  await test("Download CSV saves the service's CSV of the same request (Accept: text/csv)", async () => {
    const row = (await documentAnalyses()).find((r) => r.name === 'roll_gap');
    check(row.csv, 'the roll gap has CSV tables');
    const sent = [];
    const listen = (request) => { if (request.method() === 'POST' && request.url() === base + row.path) sent.push({ accept: request.headers().accept, body: request.postData() }); };
    page.on('request', listen);
    const saved = await downloadCsv('roll_gap');
    page.off('request', listen);
    check(sent.length === 1 && sent[0].accept === 'text/csv', `the page asked: ${JSON.stringify(sent)}`);
    const body = JSON.parse(sent[0].body);
    check(JSON.stringify(body.scenario) === JSON.stringify(patch), `the request run: ${sent[0].body}`);
    equalBytes(saved, await postCsv(row.path, body), 'roll gap CSV');
    equalBytes(saved, await postCsv(row.path, { scenario: patch }), 'roll gap CSV of the edited field');
  });

  await test('stability: damping branches, critical speed marker and mode shape are the API data', async () => {
    await page.click('#tab-stability');
    await runAndWait('damping');
    const api = (await post('/v1/stability', { scenario: patch })).body.result;
    const critical = api.critical_speed;
    const chart = await chartData('damping');
    critical.damping_branches.forEach((branch, i) => {
      const plotted = chart.datasets[i].data;
      equalArrays(plotted.map((p) => p.x), branch.speed_m_per_s, `branch ${i} speed`);
      equalArrays(plotted.map((p) => p.y), branch.damping_ratio, `branch ${i} damping ratio`);
    });
    check(dataset(chart, 'critical speed')[0].x === critical.critical_speed_m_per_s, 'critical speed marker');
    // The operating speed (the scenario's roll speed) beside it, on both charts, named with its value.
    const speed = (await post('/v1/stability', { scenario: patch })).body.scenario.rolls.speed_m_per_s;
    for (const id of ['damping', 'growth']) {
      const operating = datasetStarting(await chartData(id), 'operating speed');
      equalArrays(operating.data.map((p) => p.x), [speed, speed], `${id}: the operating speed line`);
      check(operating.label === `operating speed (roll speed ${Number(speed.toPrecision(4))} m/s)`, `${id}: ${operating.label}`);
    }
    const shape = await chartData('mode-shape');
    equalArrays(shape.datasets[0].data, critical.unstable_mode.shape, 'unstable mode shape');
    const caption = await page.textContent('figure:has(#plot-mode-shape) figcaption');
    check(caption.includes(`chatter type ${chatterNames[critical.unstable_mode.chatter_type]}`), `chatter type beside the mode shape: ${caption}`);
    check((await page.textContent('#headline')).includes(chatterNames[api.least_damped_mode.chatter_type]), 'the least-damped mode\'s chatter type in the headline');
    await shot('stability');
  });

  await test('the mode shape names the stack\'s masses as the field table does: m1 and m6 are the crossheads', async () => {
    const labels = (await chartData('mode-shape')).labels;
    check(labels.length === 6, `six masses: ${labels}`);
    const scenario = (await (await fetch(base + '/openapi.json')).json()).components.schemas.Scenario;
    const masses = scenario.properties.mill.properties.masses_t.properties;
    labels.forEach((label, i) => {
      const [name, ...words] = label.split(' ');
      check(name === `m${i + 1}`, `bar ${i} is ${label}`);
      // the part the label names is the one the field table describes
      check(masses[name].description.toLowerCase().includes(words.join(' ')),
        `${label}: the field table says ${masses[name].description}`);
    });
    check(labels[0].includes('crosshead') && labels[5].includes('crosshead'), `m1 and m6: ${labels[0]}, ${labels[5]}`);
  });

  await test('a summary stability draws no empty charts: its numbers, and how to get the curves', async () => {
    await page.selectOption('#f-options-detail', 'summary');
    const sent = await postedDuring('/v1/stability', () => runAndWait('stability-summary'));
    check(sent.length === 1 && sent[0].options.detail === 'summary', `posted ${JSON.stringify(sent)}`);
    check(!(await page.$('#plot-damping')) && !(await page.$('#plot-growth')), 'no damping or growth-rate chart without their data');
    const api = (await post('/v1/stability', sent[0])).body.result;
    check(!api.critical_speed.damping_branches && !api.critical_speed.scan, 'the summary has no curves to draw');
    // the headline shows the critical speed to 4 significant digits (views.js fmt)
    const speed = Number(api.critical_speed.critical_speed_m_per_s.toPrecision(4)).toString();
    check((await page.textContent('#headline')).includes(speed), `critical speed ${speed} in the headline`);
    check((await page.textContent('#plot-stability-summary')).includes('detail to full'), 'the note says how to get the curves');
    await page.selectOption('#f-options-detail', '');
    await runAndWait('damping');
  });

  await test('a pinned run drawn beside the next: two stabilities on the damping and growth-rate charts, the legend naming both', async () => {
    await page.click('#pin');
    const name = await page.textContent('#pinned-name');
    check(await page.isVisible('#pinned') && name === 'default stand: Reduction 0.2', `pinned: ${name}`);
    await page.fill('#f-scenario-strip-reduction', '0.25');
    await runAndWait('damping');
    const [pinnedApi, currentApi] = await Promise.all([patch, { strip: { reduction: 0.25 } }].map(async (p) => (await post('/v1/stability', { scenario: p })).body.result.critical_speed));
    await checkPinnedDamping(name, pinnedApi, currentApi);
    check((await page.textContent('figure:has(#plot-damping) figcaption')).includes(`this run (default stand: Reduction 0.25, solid) and the pinned (${name}, dashed)`), 'the caption names both runs');
    const growth = await chartData('growth');
    equalArrays(dataset(growth, `max growth rate [1/s] — pinned (${name})`).map((p) => p.y), pinnedApi.scan.map((q) => q.max_growth_rate_per_s), 'the pinned growth rate');
    equalArrays(dataset(growth, 'max growth rate [1/s] — this run (default stand: Reduction 0.25)').map((p) => p.y), currentApi.scan.map((q) => q.max_growth_rate_per_s), 'this run\'s growth rate');
    await shot('stability-pinned');
    // Unpinned: one run again, its labels as before.
    await page.click('#unpin');
    check(await page.isHidden('#pinned') && !(await chartData('damping')).datasets.some((d) => /pinned|this run/.test(d.label)), 'unpinned');
    await page.fill('#f-scenario-strip-reduction', '0.2');
    await runAndWait('damping');
  });

  let link = '';
  await test('a shared URL restores the view', async () => {
    link = page.url();
    check(link.includes('analysis=stability') && !link.includes('token'), `link: ${link}`);
    const elsewhere = await browser.newContext({ viewport: { width: 1280, height: 800 } });
    const other = watch(await elsewhere.newPage());
    await other.goto(link);
    await other.waitForSelector('#plot-damping', { timeout: 120000 });
    check(await other.inputValue('#f-scenario-strip-reduction') === '0.2', 'the edited field is restored');
    check(await other.getAttribute('#tab-stability', 'aria-selected') === 'true', 'the analysis is restored');
    const restored = await other.evaluate(() => Chart.getChart(document.getElementById('plot-damping')).data.datasets[0].data.length);
    check(restored === (await chartData('damping')).datasets[0].data.length, 'the same plot');
    await elsewhere.close();
  });

  await test('the report view renders and prints', async () => {
    await page.click('#report');
    await page.waitForSelector('body.report-mode #report-head h2');
    const head = await page.textContent('#report-head');
    const version = (await (await fetch(base + '/livez')).json()).version;
    check(head.includes(`rollgap ${version}`), `version in the report: ${head}`);
    const scenario = await page.textContent('#report-scenario');
    check(scenario.includes('/strip/reduction') && scenario.includes('/mill/masses_t/m1'), 'the full scenario is listed');
    check(await page.isHidden('#editor'), 'the editor is hidden in the report');
    // a title and an author typed in place, the stand and the date, one line that concludes
    check((await page.inputValue('#report-title')) === 'rollgap report: Stability', `title: ${await page.inputValue('#report-title')}`);
    check(head.includes('The default stand') && head.includes(new Date().toISOString().slice(0, 10)), `stand and date: ${head}`);
    const api = (await post('/v1/stability', { scenario: patch })).body;
    const v = api.scenario.rolls.speed_m_per_s;
    const vc = api.result.critical_speed.critical_speed_m_per_s;
    const short = (x) => Number(x.toPrecision(3)).toString();
    const expected = `The default stand runs at ${short(v)} m/s, ${Math.round((100 * v) / vc)} % of its ${short(vc)} m/s chatter limit.`;
    check((await page.textContent('#report-conclusion')) === expected, `conclusion: ${await page.textContent('#report-conclusion')}, expected ${expected}`);
    await page.fill('#report-author', 'A. Engineer');
    await page.click('#report');
    await page.click('#report');
    check((await page.inputValue('#report-author')) === 'A. Engineer', 'the author is kept');
    await shot('report');
    await page.emulateMedia({ media: 'print' });
    await shot('report-print');
    await page.pdf({ path: path.join(screenshots, 'report.pdf'), format: 'A4' });
    check(statSync(path.join(screenshots, 'report.pdf')).size > 10000, 'a PDF was printed');
    await page.emulateMedia({ media: 'screen' });
    await page.click('#report');
  });

  await test('a 422 is shown at the input it names', async () => {
    await page.click('#tab-roll_gap');
    await page.fill('#f-scenario-strip-reduction', '5');
    expected422 = 1;
    await page.click('#run');
    await page.waitForSelector('#f-scenario-strip-reduction-error:not([hidden])', { timeout: 30000 });
    const message = await page.textContent('#f-scenario-strip-reduction-error');
    check(/0\.7/.test(message), `message at the input: ${message}`);
    check(await page.getAttribute('#f-scenario-strip-reduction', 'aria-invalid') === 'true', 'the input is marked invalid');
    check(await page.evaluate(() => document.activeElement.id) === 'f-scenario-strip-reduction', 'focus moves to the input');
    await shot('problem');
    await page.fill('#f-scenario-strip-reduction', '0.2');
  });

  await test('amplitude with its time series: the gap and force changes over time are the API\'s series', async () => {
    await page.click('#tab-amplitude');
    await page.selectOption('#f-options-time-series', 'true');
    const sent = await postedDuring('/v1/amplitude', () => runAndWait('series-0'));
    check(sent.length === 1 && sent[0].options.time_series === true, `the page asked for the series: ${JSON.stringify(sent)}`);
    const api = (await post('/v1/amplitude', sent[0])).body.result;
    const series = api.points[0].time_series;
    const chart = await chartData('series-0');
    const gap = dataset(chart, 'gap change [µm]');
    equalArrays(gap.map((p) => p.x), series.time_s, 'time');
    equalArrays(gap.map((p) => p.y), series.work_roll_gap_change_um, 'work-roll gap change');
    equalArrays(dataset(chart, 'force change [kN]').map((p) => p.y), series.roll_force_change_kN, 'roll force change');
    await shot('amplitude-time-series');
    await page.selectOption('#f-options-time-series', '');
  });

  await test('a sweep runs as a job and plots the API data', async () => {
    await page.click('#tab-sweep');
    await page.selectOption('#f-options-parameter', '/strip/reduction');
    await page.fill('#f-options-range-from', '0.1');
    await page.fill('#f-options-range-to', '0.3');
    await page.fill('#f-options-range-count', '5');
    await runAndWait('sweep');
    const options = { parameter: '/strip/reduction', range: { from: 0.1, to: 0.3, count: 5 } };
    const api = (await post('/v1/sweeps', { scenario: patch, options })).body.result;
    const chart = await chartData('sweep');
    const plotted = dataset(chart, 'critical speed [m/s]');
    equalArrays(plotted.map((p) => p.x), api.points.map((p) => p.value), 'swept values');
    equalArrays(plotted.map((p) => p.y), api.points.map((p) => p.critical_speed_m_per_s), 'critical speeds');
    check(/job succeeded/.test(await page.textContent('#status')), 'status says the job succeeded');
    // The operating speed across the swept values: the margin to each critical speed.
    const speed = (await post('/v1/sweeps', { scenario: patch, options })).body.scenario.rolls.speed_m_per_s;
    const operating = datasetStarting(chart, 'operating speed').data;
    equalArrays(operating.map((p) => p.y), [speed, speed], 'the operating speed line');
    equalArrays(operating.map((p) => p.x), [api.points[0].value, api.points.at(-1).value], 'across the swept values');
    check((await page.$$('#job-list li')).length >= 1, 'the job is listed');
    await shot('sweep');
    // A job's result: its CSV is the service's for the same request.
    equalBytes(await downloadCsv('sweep'), await postCsv('/v1/sweeps', { scenario: patch, options }), 'sweep CSV');
  });

  await test('a sweep over a field with a unit: chatter type per point, its changes marked, finished points drawn while it runs', async () => {
    const options = { parameter: '/strip/flow_stress_MPa', range: { from: 500, to: 1000, count: 6 } };
    const api = (await post('/v1/sweeps', { scenario: patch, options })).body.result;
    check(api.chatter_type_changes.length >= 1, 'the sweep chosen has a change of chatter type');
    await page.selectOption('#f-options-parameter', options.parameter);
    await page.fill('#f-options-range-from', '500');
    await page.fill('#f-options-range-to', '1000');
    await page.fill('#f-options-range-count', '6');
    // While the job runs: points 1 and 4 done (the contract of a chunked job's partial_result).
    const release = await holdJob((job) => ({ ...job, state: 'running', result: undefined, progress: 0.33, points_total: 6, points_done: 2,
      partial_result: { partial: true, points_total: 6, points_done: 2, points: [1, 4].map((i) => ({ index: i, point: api.points[i] })) } }));
    await page.evaluate(() => document.getElementById('plots').replaceChildren());
    await page.click('#run');
    await page.waitForSelector('#plot-sweep', { timeout: 60000 });
    const partial = dataset(await chartData('sweep'), 'critical speed [m/s]');
    equalArrays(partial.map((p) => p.x), api.points.map((p) => p[api.value_name]), 'swept values while running');
    equalArrays(partial.map((p) => p.y), api.points.map((p, i) => ([1, 4].includes(i) ? p.critical_speed_m_per_s : null)), 'finished points while running');
    check(/2 of 6 points/.test(await page.textContent('#status')), 'the status counts the points');
    await shot('sweep-running');
    await release();
    await page.waitForFunction(() => /job succeeded/.test(document.getElementById('status').textContent), null, { timeout: 120000 });
    const chart = await chartData('sweep');
    equalArrays(dataset(chart, 'critical speed [m/s]').map((p) => p.x), api.points.map((p) => p[api.value_name]), `swept values (${api.value_name})`);
    for (const [type, name] of Object.entries(chatterNames)) {
      const expected = api.points.filter((p) => p.chatter_type === type);
      const found = chart.datasets.find((d) => d.label === `chatter type ${name}`);
      check(expected.length === (found ? found.data.length : 0), `${name}: ${found ? found.data.length : 0} points drawn, the API has ${expected.length}`);
      if (found) equalArrays(found.data.map((p) => p.x), expected.map((p) => p[api.value_name]), `${name} points`);
    }
    const flowStress = (await (await fetch(base + '/openapi.json')).json()).components.schemas.Scenario.properties.strip.properties.flow_stress_MPa;
    const titles = await axisTitles('sweep');
    check(titles.x === `${flowStress.title} [${flowStress['x-unit']}]` && titles.y === 'critical speed [m/s]', `axes: ${JSON.stringify(titles)}`);
    const changes = chart.datasets.filter((d) => d.label === 'chatter type changes');
    equalArrays(changes.map((d) => d.data[0].x), api.chatter_type_changes.map((c) => (c.from + c.to) / 2), 'chatter type change markers');
    check((await page.textContent('#headline')).includes(`${chatterNames[api.chatter_type_changes[0].from_chatter_type]} → ${chatterNames[api.chatter_type_changes[0].to_chatter_type]}`), 'the change is listed');
    await shot('sweep-chatter-types');
  });

  await test('plant units: speeds in m/min and viscosities in mPa·s on the axes and in the table, the CSV asked with ?units=plant, kept in the link', async () => {
    // The flow-stress sweep of the test before is on screen.
    const options = { parameter: '/strip/flow_stress_MPa', range: { from: 500, to: 1000, count: 6 } };
    const api = (await post('/v1/sweeps', { scenario: patch, options })).body.result;
    await page.check('#units-plant');
    try {
      check(page.url().includes('units=plant'), `the units are in the link: ${page.url()}`);
      let chart = await chartData('sweep');
      equalArrays(dataset(chart, 'critical speed [m/min]').map((p) => p.y), api.points.map((p) => (p.critical_speed_m_per_s === null ? null : p.critical_speed_m_per_s * 60)), 'critical speeds in m/min');
      equalArrays(dataset(chart, 'critical speed [m/min]').map((p) => p.x), api.points.map((p) => p[api.value_name]), 'flow stresses (MPa either way)');
      check((await axisTitles('sweep')).y === 'critical speed [m/min]', `y axis: ${(await axisTitles('sweep')).y}`);
      // The CSV: the service's in plant units, for the job shown.
      const sent = [];
      const listen = (request) => { if (/\/v1\/jobs\/[0-9a-f]{32}/.test(request.url()) && request.headers().accept === 'text/csv') sent.push(request.url()); };
      page.on('request', listen);
      const saved = await downloadCsv('sweep');
      page.off('request', listen);
      check(sent.length === 1 && new URL(sent[0]).searchParams.get('units') === 'plant', `the page asked ${sent}`);
      const served = await postCsv('/v1/sweeps?units=plant', { scenario: patch, options });
      equalBytes(saved, served, 'sweep CSV in plant units');
      check(/critical_speed_m_per_min/.test(saved.toString('utf8').split('\n')[0]), `plant header: ${saved.toString('utf8').split('\n')[0]}`);
      // A viscosity swept: its axis in mPa·s, the values the API's × 1000.
      const viscosity = { parameter: '/lubricant/viscosity_Pa_s', values: [0.0004, 0.0006] };
      await page.selectOption('#f-options-parameter', viscosity.parameter);
      for (const id of ['#f-options-range-from', '#f-options-range-to', '#f-options-range-count']) await page.fill(id, '');
      await page.fill('#f-options-values', viscosity.values.join(', '));
      await runAndWait('sweep');
      await page.waitForFunction(() => /job succeeded/.test(document.getElementById('status').textContent), null, { timeout: 60000 });
      const viscous = (await post('/v1/sweeps', { scenario: patch, options: viscosity })).body.result;
      chart = await chartData('sweep');
      equalArrays(dataset(chart, 'critical speed [m/min]').map((p) => p.x), viscous.points.map((p) => p[viscous.value_name] * 1000), 'viscosities in mPa·s');
      check((await axisTitles('sweep')).x === 'Lubricant viscosity [mPa·s]', `x axis: ${(await axisTitles('sweep')).x}`);
      // Pinned, and the same sweep on a thinner pass: both runs' critical speeds, each the API's, named.
      await page.click('#pin');
      await page.fill('#f-scenario-strip-reduction', '0.25');
      await runAndWait('sweep');
      await page.waitForFunction(() => /job succeeded/.test(document.getElementById('status').textContent), null, { timeout: 60000 });
      const thinner = (await post('/v1/sweeps', { scenario: { strip: { reduction: 0.25 } }, options: viscosity })).body.result;
      chart = await chartData('sweep');
      const m = (points) => points.map((p) => (p.critical_speed_m_per_s === null ? null : p.critical_speed_m_per_s * 60));
      equalArrays(dataset(chart, 'critical speed [m/min] — pinned (default stand: Reduction 0.2)').map((p) => p.y), m(viscous.points), 'the pinned sweep');
      equalArrays(dataset(chart, 'critical speed [m/min] — this run (default stand: Reduction 0.25)').map((p) => p.y), m(thinner.points), 'this run\'s sweep');
      await page.click('#unpin');
      await page.fill('#f-scenario-strip-reduction', '0.2');
      // Opened again from the link: still in plant units.
      await page.reload();
      await page.waitForSelector('body[data-ready="true"]');
      check(await page.isChecked('#units-plant'), 'plant units after a reload');
    } finally {  // the tests after this one read SI numbers from one run
      if (await page.isVisible('#unpin')) await page.click('#unpin');
      await page.fill('#f-scenario-strip-reduction', '0.2');
      await page.check('#units-si');
      await page.fill('#f-options-values', '');
    }
    check(!page.url().includes('units='), `SI is the default: ${page.url()}`);
  });

  await test('plant units in the editor: a speed typed in m/min and a viscosity in mPa·s are sent in SI, as the API converts its plant keys', async () => {
    await page.click('#tab-roll_gap');
    const speed = '#f-scenario-rolls-speed-m-per-s';
    const viscosity = '#f-scenario-lubricant-viscosity-Pa-s';
    const [speedSi, viscositySi] = [Number(await page.inputValue(speed)), Number(await page.inputValue(viscosity))];
    const diffPointers = () => page.$$eval('#diff li', (all) => all.map((li) => li.dataset.pointer));
    const diffBefore = await diffPointers();
    await page.check('#units-plant');
    try {
      // The same values in the units shown, the labels saying so; switching changes nothing.
      check(Number(await page.inputValue(speed)) === speedSi * 60, `the roll speed shown: ${await page.inputValue(speed)} for ${speedSi} m/s`);
      check(await page.textContent(`label[for="${speed.slice(1)}"] .unit`) === ' [m/min]', 'the speed in m/min');
      check(Number(await page.inputValue(viscosity)) === Number((viscositySi * 1000).toPrecision(12)), `the viscosity shown: ${await page.inputValue(viscosity)} for ${viscositySi} Pa·s`);
      check(await page.textContent(`label[for="${viscosity.slice(1)}"] .unit`) === ' [mPa·s]', 'the viscosity in mPa·s');
      equalArrays(await diffPointers(), diffBefore, 'switching units changes no field');
      // Typed in plant units: the request carries the SI values the API makes of the plant keys.
      await page.fill(speed, '1200');
      await page.fill(viscosity, '0.7');
      const sent = await postedDuring('/v1/roll-gap', () => runAndWait('pressure'));
      const api = (await post('/v1/roll-gap', { scenario: { ...patch, rolls: { speed_m_per_min: 1200 }, lubricant: { viscosity_mPa_s: 0.7 } } })).body.scenario;
      check(sent.length === 1 && sent[0].scenario.rolls.speed_m_per_s === api.rolls.speed_m_per_s && api.rolls.speed_m_per_s === 20, `speed sent ${JSON.stringify(sent[0] && sent[0].scenario.rolls)}, the API's ${api.rolls.speed_m_per_s}`);
      check(sent[0].scenario.lubricant.viscosity_Pa_s === api.lubricant.viscosity_Pa_s && api.lubricant.viscosity_Pa_s === 0.0007, `viscosity sent ${JSON.stringify(sent[0].scenario.lubricant)}, the API's ${api.lubricant.viscosity_Pa_s}`);
      const speedChange = await page.textContent('#diff li[data-pointer="/rolls/speed_m_per_s"]');
      check(speedChange === `Roll speed [m/min]: ${speedSi * 60} → 1200`, `the change in m/min: ${speedChange}`);
      // An option in m/s too: its default and bound in m/min.
      await page.click('#tab-stability');
      check(await page.getAttribute('#f-options-speed-max-m-per-s', 'placeholder') === 'default 3600', `highest search speed: ${await page.getAttribute('#f-options-speed-max-m-per-s', 'placeholder')}`);
      await page.fill('#f-options-speed-max-m-per-s', '2400');
      check(JSON.stringify(await page.evaluate(() => document.getElementById('f-options-speed-max-m-per-s').value)) === '"2400"', 'typed in m/min');
      await page.check('#units-si');
      check(await page.inputValue('#f-options-speed-max-m-per-s') === '40' && await page.inputValue(speed) === '20' && await page.inputValue(viscosity) === '0.0007', 'back in SI: the same values');
    } finally {  // the tests after this one start from the editor as it was
      await page.check('#units-si');
      await page.fill('#f-options-speed-max-m-per-s', '');
      await page.fill(speed, String(speedSi));
      await page.fill(viscosity, String(viscositySi));
      await page.click('#tab-roll_gap');
    }
    equalArrays(await diffPointers(), diffBefore, 'the editor as it was');
  });

  // A 3 x 4 map with changes of chatter type and cells stable over the whole search range.
  const mapOptions = { parameters: [
    { parameter: '/mill/rayleigh/damping_ratio', values: [0.03, 0.06, 0.1] },
    { parameter: '/strip/flow_stress_MPa', values: [400, 600, 800, 1000] },
  ] };
  await test('map: cell colours, chatter types, type changes and the stable window are the API data', async () => {
    const options = mapOptions;
    const response = (await post('/v1/maps', { scenario: patch, options })).body;
    const api = response.result;
    await page.click('#tab-map');
    // The two axes as rows: a field picked by its title (its unit beside it), a range or values.
    const rows = await page.$$eval('#f-options-parameters-0-parameter option', (all) => all.map((o) => [o.value, o.textContent]));
    check(rows.some(([v, text]) => v === '/strip/flow_stress_MPa' && text === 'Flow stress [MPa]') && !rows.some(([v]) => v === '/rolls/speed_m_per_s'), 'the map\'s fields by title (not the roll speed)');
    await fillRows('f-options-parameters', [{ parameter: '/mill/rayleigh/damping_ratio', 'range/from': 0.03, 'range/to': 0.1, 'range/count': 3 }, { parameter: '/strip/flow_stress_MPa' }]);
    check(canon(await listValue('f-options-parameters')) === canon([{ parameter: '/mill/rayleigh/damping_ratio', range: { from: 0.03, to: 0.1, count: 3 } }, { parameter: '/strip/flow_stress_MPa' }]), `the axes: ${JSON.stringify(await listValue('f-options-parameters'))}`);
    check(await page.textContent('#f-options-parameters-1-parameter >> xpath=../following-sibling::td[1]') === 'MPa', 'the unit beside the field');
    // Values typed replace the range (one of the two).
    await fillRows('f-options-parameters', [{ 'range/from': '', 'range/to': '', 'range/count': '', values: '0.03, 0.06, 0.1' }, { values: '400, 600, 800, 1000' }]);
    check(canon(await listValue('f-options-parameters')) === canon(options.parameters), `the axes: ${JSON.stringify(await listValue('f-options-parameters'))}`);
    // A list pasted as JSON fills the rows.
    await page.click('#f-options-parameters >> xpath=ancestor::details[1]/summary');
    await page.fill('#f-options-parameters', JSON.stringify([{ parameter: '/strip/reduction', range: { from: 0.1, to: 0.3, count: 4 } }, options.parameters[1]]));
    check(await page.inputValue('#f-options-parameters-0-parameter') === '/strip/reduction' && await page.inputValue('#f-options-parameters-0-range-count') === '4', 'the pasted axes in the rows');
    await page.fill('#f-options-parameters', JSON.stringify(options.parameters));
    await page.click('#f-options-parameters >> xpath=ancestor::details[1]/summary');
    // While the job runs: cells 0, 5 and 11 done.
    const doneCells = [0, 5, 11];
    const release = await holdJob((job) => ({ ...job, state: 'running', result: undefined, progress: 0.25, points_total: 12, points_done: 3,
      partial_result: { partial: true, points_total: 12, points_done: 3, points: doneCells.map((i) => ({ index: i, point: api.cells[i] })) } }));
    await page.evaluate(() => document.getElementById('plots').replaceChildren());
    await page.click('#run');
    await page.waitForSelector('#plot-map', { timeout: 60000 });
    const running = await heatmap();
    equalArrays(running.values, api.cells.map((c, i) => (doneCells.includes(i) ? c.critical_speed_m_per_s : null)), 'cells while running');
    await shot('map-running');
    await release();
    await page.waitForFunction(() => /job succeeded/.test(document.getElementById('status').textContent), null, { timeout: 120000 });
    const drawn = await heatmap();
    equalArrays(drawn.rows, api.parameters[0].values, 'row values');
    equalArrays(drawn.columns, api.parameters[1].values, 'column values');
    const doc = await (await fetch(base + '/openapi.json')).json();
    const stressUnit = doc.components.schemas.Scenario.properties.strip.properties.flow_stress_MPa['x-unit'];
    const titles = [doc.components.schemas.Scenario.properties.mill.properties.rayleigh.properties.damping_ratio.title, doc.components.schemas.Scenario.properties.strip.properties.flow_stress_MPa.title];
    equalArrays(drawn.axes, [titles[0], `${titles[1]} [${stressUnit}]`], 'axis titles: the document\'s titles and units');
    equalArrays(drawn.values, api.cells.map((c) => c.critical_speed_m_per_s), 'critical speed per cell');
    const found = api.cells.map((c) => c.critical_speed_m_per_s).filter((v) => v !== null);
    check(drawn.legend.min === Math.min(...found) && drawn.legend.max === Math.max(...found), `legend ${drawn.legend.min}..${drawn.legend.max}`);
    drawn.values.forEach((v, k) => {
      if (v === null) return;
      check(drawn.pixels[k].every((c, i) => Math.abs(c - drawn.colours[k][i]) <= 1), `cell ${k}: drawn ${drawn.pixels[k]}, its value's colour ${drawn.colours[k]}`);
    });
    check(new Set(drawn.colours.filter(Boolean).map(String)).size > 1, 'different values, different colours');
    // Each cell says its critical speed (3 digits) and its chatter type as a symbol, the legend names them.
    const symbols = { third_octave: '●', fifth_octave: '▲', other: '■' };
    const classLetters = { stable_in_range: 'S', unstable_at_lower_bound: 'U', no_steady_state: '×' };
    equalArrays(drawn.symbols, api.cells.map((c) => (c.chatter_type ? symbols[c.chatter_type] : classLetters[c.status])), 'symbols');
    equalArrays(drawn.texts, api.cells.map((c, k) => (c.critical_speed_m_per_s === null ? drawn.symbols[k] : `${Number(c.critical_speed_m_per_s.toPrecision(3))} ${drawn.symbols[k]}`)), 'the numbers in the cells');
    const legend = await page.$$eval('#map-legend li', (all) => Object.fromEntries(all.map((li) => [li.dataset.symbol, li.textContent])));
    for (const [type, symbol] of Object.entries(symbols)) check(legend[symbol] && legend[symbol].includes(chatterNames[type]), `legend of ${symbol}: ${legend[symbol]}`);
    for (const letter of Object.values(classLetters)) check(legend[letter], `legend of ${letter}`);
    const at = (values) => api.cells.findIndex((c) => c.values[0] === values[0] && c.values[1] === values[1]);
    equalArrays(drawn.edges.map(String), api.chatter_type_changes.map((c) => String([at(c.from), at(c.to)])), 'chatter type change edges');
    check(api.chatter_type_changes.length > 0, 'the map chosen has type changes');
    const stableAt = (speed) => api.cells.map((c) => c.status === 'stable_in_range' || (c.critical_speed_m_per_s !== null && speed < c.critical_speed_m_per_s));
    check(drawn.speed === response.scenario.rolls.speed_m_per_s, 'operating speed: the scenario\'s');
    equalArrays(drawn.stable, stableAt(drawn.speed), 'stable cells at the scenario speed');
    await page.fill('#map-speed', '30');
    equalArrays((await heatmap()).stable, stableAt(30), 'stable cells at 30 m/s');
    await page.fill('#map-speed', String(response.scenario.rolls.speed_m_per_s));
    await shot('map');
    await checkAxe();
  });

  await test('speed limit: every checked limit on one speed axis, the binding one marked, the window and the speeds are the API data', async () => {
    await page.click('#reset');
    await page.click('#tab-speed_limit');
    await page.fill('#f-options-max-roll-force-kN', '7000');
    await page.fill('#f-options-max-power-kW', '6000');
    await page.fill('#f-options-min-forward-slip', '0.005');
    await page.fill('#f-options-chatter-margin', '0.05');
    const sent = await postedDuring('/v1/speed-limit', () => runAndWait('speed-limits'));
    check(sent.length === 1 && sent[0].options.max_roll_force_kN === 7000 && sent[0].options.max_power_kW === 6000, `the page sent: ${JSON.stringify(sent)}`);
    const api = (await post('/v1/speed-limit', sent[0])).body.result;
    check(api.status === 'ok' && api.binding_limit, `the API's answer: ${api.status}, binding ${api.binding_limit}`);
    const chart = await chartData('speed-limits');
    const names = { force: 'roll force', torque: 'torque', power: 'motor power', skid: 'skid (forward slip)', chatter: 'chatter' };
    // Each checked limit's bar spans the speeds its own answer gives, the binding one named so.
    for (const l of api.limits.filter((x) => x.limit !== 'steady_state')) {
      const binding = l.limit === api.binding_limit || l.limit === api.binding_min;
      const bar = dataset(chart, `${names[l.limit]} permits${binding ? ' (binding)' : ''}`);
      check(bar.length === 2, `a bar for ${l.limit}`);
      if (l.lower_speed_m_per_s !== null) check(bar[0].x === l.lower_speed_m_per_s, `${l.limit} from ${bar[0].x}, the API ${l.lower_speed_m_per_s}`);
      if (l.upper_speed_m_per_s !== null) check(bar[1].x === l.upper_speed_m_per_s, `${l.limit} to ${bar[1].x}, the API ${l.upper_speed_m_per_s}`);
    }
    const window = dataset(chart, 'permitted window');
    check(window[0].x === api.window_min_m_per_s && window[1].x === api.window_max_m_per_s, `window ${JSON.stringify(window)}`);
    check(dataset(chart, 'advised speed')[0].x === api.advised_speed_m_per_s, 'the advised speed line');
    check(dataset(chart, 'operating speed')[0].x === api.operating_speed_m_per_s, 'the operating speed line');
    const headline = await page.textContent('#headline');
    check(headline.includes(api.summary), `headline: ${headline}`);
    // The table of the limits: one row per checked limit, its utilisation the API's.
    const cells = await page.$$eval('#plots table:first-of-type tbody tr', (rows) => rows.map((tr) => [...tr.cells].map((c) => c.dataset.value ?? c.textContent)));
    equalArrays(cells.map((c) => c[0]), api.limits.map((l) => names[l.limit] || 'steady state'), 'the limits in the table');
    const measured = api.limits.map((l, i) => [l, cells[i]]).filter(([l]) => l.utilisation !== null);
    check(measured.length >= 3, `utilisations at the operating speed: ${measured.length}`);
    equalArrays(measured.map(([, c]) => Number(c[4])), measured.map(([l]) => l.utilisation), 'utilisations');
    check(chart.datasets.every((d) => !d.label.startsWith('critical speed:')), 'no uncertainty band without a posterior');
    // A posterior on the viscosity (centred on the default stand): the chatter lane carries the
    // band from the 95 % lower bound to the mean, the numbers the API gives.
    await page.fill('#f-options-posterior-parameters', JSON.stringify([{ field: '/lubricant/viscosity_Pa_s', value: 0.00055, standard_error: 0.00002 }]));
    const withPosterior = await postedDuring('/v1/speed-limit', () => runAndWait('speed-limits'));
    const u = (await post('/v1/speed-limit', withPosterior[0])).body.result.uncertainty;
    check(u && u.propagated && u.standard_deviation_m_per_s > 0, `the API's uncertainty: ${JSON.stringify(u)}`);
    const banded = await chartData('speed-limits');
    const band = banded.datasets.find((d) => d.label.startsWith('critical speed:'));
    check(band && band.data[0].x === u.lower_bound_m_per_s && band.data[1].x === u.critical_speed_m_per_s, `band ${JSON.stringify(band && band.data)}, the API ${u.lower_bound_m_per_s} to ${u.critical_speed_m_per_s}`);
    // The headline shows it to 4 significant digits (views.js fmt).
    const sigma = Number(u.standard_deviation_m_per_s.toPrecision(4)).toString();
    check((await page.textContent('#headline')).includes(sigma), `σ ${sigma} in the headline`);
    await shot('speed-limit');
    await checkAxe();
    for (const id of ['#f-options-max-roll-force-kN', '#f-options-max-power-kW', '#f-options-min-forward-slip', '#f-options-chatter-margin', '#f-options-posterior-parameters']) await page.fill(id, '');
  });

  await test('batch: a batch job opened from the job list is a table of its coils, sorted by margin and by any column', async () => {
    const coils = [16, 21, 18, 19.5, 14].map((speed, i) => ({ label: `C-${700 + i}`, scenario: { rolls: { speed_m_per_s: speed } } }));
    coils.push({ label: 'C-bad', scenario: { strip: { reduction: 2 } } });
    const options = { analysis: 'speed_limit', options: { max_roll_force_kN: 7000, speed_min_m_per_s: 10, speed_max_m_per_s: 30 }, items: coils };
    const submitted = await post('/v1/batches', { options });
    check(submitted.status === 202, `POST /v1/batches answered ${submitted.status}`);
    let job;
    for (let i = 0; i < 200; i++) {
      job = await (await fetch(`${base}/v1/jobs/${submitted.body.id}`)).json();
      if (job.state === 'succeeded') break;
      await new Promise((resolve) => setTimeout(resolve, 100));
    }
    check(job.state === 'succeeded', `the batch ended ${job.state}`);
    const rows = job.result.result.items;
    // The page anew without a view in its link: a link's view would run at once and, under the
    // sanitizers, could draw over the batch after it is opened.
    await page.goto(base + '/');
    await page.waitForSelector('body[data-ready="true"]');
    const open = page.locator('#job-list button', { hasText: /^batch · succeeded/ }).first();
    await open.waitFor({ timeout: 30000 });
    await open.click();
    await page.waitForSelector('#batch-table tbody tr');
    const shown = () => page.$$eval('#batch-table tbody tr', (trs) => trs.map((tr) => ({ index: Number(tr.dataset.index), cells: [...tr.cells].map((c) => c.dataset.value ?? c.textContent) })));
    const margin = (r) => (r.headline ? r.headline.speed_margin_m_per_s : null);
    const byMargin = [...rows].sort((a, b) => ((margin(a) === null) - (margin(b) === null)) || margin(a) - margin(b));
    let table = await shown();
    equalArrays(table.map((r) => r.index), byMargin.map((r) => r.index), 'rows by margin, the tightest first, the failed coil last');
    equalArrays(table.filter((r) => r.index !== 5).map((r) => Number(r.cells[2])), byMargin.filter((r) => r.headline).map(margin), 'margins are the API\'s');
    check(table[table.length - 1].cells[1] === 'failed' && table[table.length - 1].cells.at(-1).includes('0.7'), `the failed coil's problem: ${JSON.stringify(table.at(-1))}`);
    await page.click('#batch-sort-speed-margin-m-per-s');
    table = await shown();
    equalArrays(table.slice(0, 5).map((r) => r.index), byMargin.slice(0, 5).reverse().map((r) => r.index), 'the margin descending');
    await page.click('#batch-sort-label');
    table = await shown();
    equalArrays(table.map((r) => r.cells[0]), [...rows].map((r) => r.label).sort((a, b) => a.localeCompare(b)), 'by coil');
    check((await page.textContent('#headline')).includes('with a problem'), 'the headline counts the coils with a problem');
    await shot('batch');
    await checkAxe();
  });

  await test('calibration: observed vs fitted with error bars, the fitted values and standard errors are the API data', async () => {
    // The calibration example of docs/cli.md (examples/calibrate.json) without its
    // critical-speed observations and the span length only they determine: a critical-speed
    // search per evaluation makes the full fit 4x dearer, and this suite runs under the
    // sanitizers too.
    const example = JSON.parse(readFileSync(new URL('../../examples/calibrate.json', import.meta.url), 'utf8')).options;
    const options = {
      parameters: example.parameters.filter((p) => p.field !== '/tension/back/span_length_m'),
      observations: example.observations.filter((o) => !['critical_speed_m_per_s', 'chatter_frequency_Hz'].includes(o.quantity)),
    };
    await page.click('#reset');  // the calibration example starts from the default scenario
    await page.click('#tab-calibrate');
    // The fields to fit picked by title, their bounds as placeholders; the measurements as a table.
    await fillRows('f-options-parameters', options.parameters.map((p) => ({ field: p.field, min: p.min, max: p.max })));
    const doc = await (await fetch(base + '/openapi.json')).json();
    const titleOf = (pointer) => pointer.split('/').slice(1).reduce((node, key) => node.properties[key], doc.components.schemas.Scenario);
    check(await page.getAttribute('#f-options-parameters-0-min', 'placeholder') === String(titleOf('/strip/flow_stress_MPa').minimum ?? titleOf('/strip/flow_stress_MPa').exclusiveMinimum), 'the field\'s lower bound as the placeholder');
    await fillRows('f-options-observations', options.observations.map((o) => ({
      quantity: o.quantity, value: o.value, standard_uncertainty: o.standard_uncertainty,
      ...(o.scenario ? { 'scenario/rolls/speed_m_per_s': o.scenario.rolls.speed_m_per_s } : {}),
      ...(o.mode ? { 'mode/near_frequency_Hz': o.mode.near_frequency_Hz } : {}),
    })));
    check(canon(await listValue('f-options-parameters')) === canon(options.parameters) && canon(await listValue('f-options-observations')) === canon(options.observations),
      `the rows make the example's options: ${JSON.stringify(await listValue('f-options-observations'))}`);
    // The measured quantities offered by the document's titles and units (x-enum-descriptions,
    // x-units), their names the values sent.
    const quantity = doc.components.schemas.CalibrateOptions.properties.observations.items.properties.quantity;
    const offered = await page.$$eval('#f-options-observations-0-quantity option', (all) => all.filter((o) => o.value).map((o) => [o.value, o.textContent]));
    equalArrays(offered.map(([v]) => v), quantity.enum, 'the quantities offered');
    offered.forEach(([value, text], i) => {
      const unit = quantity['x-units'][i] === '1' ? '' : ` [${quantity['x-units'][i].replace('.', '·')}]`;
      check(text === `${quantity['x-enum-descriptions'][i]}${unit}`, `${value} offered as ${text}`);
    });
    check(offered.some(([v, text]) => v === 'roll_force_kN' && text === 'Roll force [kN]'), 'the roll force in kN');
    const [api, sent] = await Promise.all([post('/v1/calibrate', { options }).then((r) => r.body.result), postedDuring('/v1/jobs', () => runAndWait('calibration-residuals'))]);
    check(sent.length === 1 && canon(sent[0].options) === canon(options), `the page sent: ${JSON.stringify(sent.map((b) => b.options))}`);
    await page.waitForFunction(() => /job succeeded/.test(document.getElementById('status').textContent), null, { timeout: 120000 });
    const cells = await page.$$eval('#plots table:first-of-type tbody tr', (rows) => rows.map((tr) => [...tr.cells].map((c) => c.dataset.value ?? c.textContent)));
    const fittedFields = await page.$$eval('#plots table:first-of-type tbody tr', (rows) => rows.map((tr) => tr.title));
    equalArrays(fittedFields, api.parameters.map((p) => p.field), 'fitted fields (the rows\' pointers)');
    equalArrays(cells.map((c) => c[0]), api.parameters.map((p) => titleOf(p.field).title), 'fitted fields by their titles');
    equalArrays(cells.map((c) => Number(c[3])), api.parameters.map((p) => p.value), 'fitted values');
    equalArrays(cells.map((c) => Number(c[4])), api.parameters.map((p) => p.standard_error), 'standard errors');
    equalArrays(cells.map((c) => c[1]), api.parameters.map((p) => (p.unit === '1' ? '-' : p.unit)), 'units');
    for (const quantity of new Set(api.observations.map((o) => o.quantity))) {
      const chart = await chartData(`calibration-${quantity}`);
      const mine = api.observations.filter((o) => o.quantity === quantity);
      const observed = await page.evaluate((id) => Chart.getChart(document.getElementById(id)).data.datasets[0].data, `plot-calibration-${quantity}`);
      equalArrays(observed.map((p) => p.y), mine.map((o) => o.value), `${quantity} observed`);
      equalArrays(observed.map((p) => p.yError), mine.map((o) => o.standard_uncertainty), `${quantity} error bars`);
      equalArrays(dataset(chart, 'fitted').map((p) => p.y), mine.map((o) => o.predicted), `${quantity} fitted`);
    }
    equalArrays((await chartData('calibration-residuals')).datasets[0].data, api.observations.map((o) => o.normalised_residual), 'normalised residuals');
    const headline = await page.textContent('#headline');
    check(headline.includes('χ² of the observations') && headline.includes(api.status), `headline: ${headline}`);
    check((await page.$$('#calibration-warnings li')).length === Math.max(1, api.warnings.length), 'warnings listed');
    await shot('calibration');
    await checkAxe();
    await page.click('#use-calibrated');
    for (const p of api.parameters) {
      const id = `#f-scenario${p.field.replace(/[^A-Za-z0-9]+/g, '-')}`;
      check(Number(await page.inputValue(id)) === p.value, `${p.field} in the editor: ${await page.inputValue(id)}, fitted ${p.value}`);
    }
    check(new RegExp(`${api.parameters.length} fields differ`).test(await page.textContent('#diff-count')), `diff: ${await page.textContent('#diff-count')}`);
    await page.click('#reset');
    await page.fill('#f-scenario-strip-reduction', '0.2');
    await page.click('#tab-sweep');
    await page.selectOption('#f-options-parameter', '/strip/reduction');
    await page.fill('#f-options-range-from', '0.1');
    await page.fill('#f-options-range-to', '0.3');
  });

  await test("a job's progress moves and cancel stops it", async () => {
    await page.fill('#f-options-range-count', '400');
    await page.click('#run');
    await page.waitForFunction(() => document.getElementById('progress').value > 0, null, { timeout: 120000 });
    await shot('job-running');
    await page.click('#cancel');
    await page.waitForFunction(() => /job cancelled/.test(document.getElementById('status').textContent), null, { timeout: 60000 });
    check(await page.isHidden('#result-actions') && (await page.$$('#plots canvas')).length === 0, 'the earlier result is cleared');
  });

  await test('no serious or critical axe-core violations (workbench and report)', async () => {
    await page.click('#tab-roll_gap');
    await runAndWait('pressure');
    await page.evaluate(axeSource);
    const audit = () => page.evaluate(async () => (await axe.run(document, { resultTypes: ['violations'] })).violations
      .filter((v) => v.impact === 'serious' || v.impact === 'critical')
      .map((v) => `${v.impact} ${v.id}: ${v.help} (${v.nodes.slice(0, 3).map((n) => n.target.join(' ')).join('; ')})`));
    const found = await audit();
    await page.click('#report');
    found.push(...await audit());
    await page.click('#report');
    check(found.length === 0, found.join('\n'));
  });

  await test('links: one without its required options says what is missing (no 422); a changed fragment shows its view', async () => {
    const elsewhere = await browser.newContext({ viewport: { width: 1280, height: 800 } });
    const other = watch(await elsewhere.newPage());
    const posted = [];
    other.on('request', (request) => { if (request.method() === 'POST') posted.push(request.url()); });
    await other.goto(`${base}/#${new URLSearchParams({ analysis: 'sweep' })}`);
    await other.waitForSelector('body[data-ready="true"]');
    check(/choose parameter/.test(await other.textContent('#status')), `status: ${await other.textContent('#status')}`);
    check(await other.isHidden('#problem'), 'no problem shown before any input');
    check(posted.length === 0, `nothing posted: ${posted}`);
    // the fragment changed in place (a pasted link, the back button): its view, run
    const next = new URLSearchParams({ analysis: 'stability', scenario: JSON.stringify({ strip: { reduction: 0.25 } }) });
    await other.evaluate((hash) => { location.hash = hash; }, next.toString());
    await other.waitForSelector('#plot-damping', { timeout: 120000 });
    check(await other.getAttribute('#tab-stability', 'aria-selected') === 'true', 'the analysis of the new fragment');
    check(await other.inputValue('#f-scenario-strip-reduction') === '0.25', 'its field');
    const api = (await post('/v1/stability', { scenario: { strip: { reduction: 0.25 } } })).body.result;
    const speed = Number(api.critical_speed.critical_speed_m_per_s.toPrecision(4)).toString();
    check((await other.textContent('#headline')).includes(speed), `its critical speed ${speed}`);
    await elsewhere.close();
  });

  await test('usable at 1024 x 768 with touch', async () => {
    const tablet = await browser.newContext({ viewport: { width: 1024, height: 768 }, hasTouch: true });
    const touch = watch(await tablet.newPage());
    await touch.goto(link);
    await touch.waitForSelector('#plot-damping', { timeout: 120000 });
    const width = await touch.evaluate(() => document.documentElement.scrollWidth);
    check(width <= 1024, `the page is ${width} px wide at 1024`);
    await shot('touch-1024x768', touch);
    const map = new URLSearchParams({ analysis: 'map', options: JSON.stringify(mapOptions) });
    await touch.goto(`${base}/#${map}`);
    await touch.reload();
    await touch.waitForSelector('body[data-ready="true"]');
    // a map runs as a job: a link to one waits for Run; its axes in the rows
    check(/press Run/.test(await touch.textContent('#status')), `status: ${await touch.textContent('#status')}`);
    check(await touch.inputValue('#f-options-parameters-1-values') === mapOptions.parameters[1].values.join(', '), 'the link\'s axes in the rows');
    await touch.click('#run');
    await touch.waitForSelector('#plot-map', { timeout: 120000 });
    const mapWidth = await touch.evaluate(() => document.documentElement.scrollWidth);
    check(mapWidth <= 1024, `the map view is ${mapWidth} px wide at 1024`);
    await shot('map-1024x768', touch);
    await tablet.close();
  });

  await test('a stored scenario as the base (real store), and the service\'s job list in pages', async () => {
    const scenarios = await browser.newContext({ viewport: { width: 1280, height: 800 } });
    const other = watch(await scenarios.newPage());
    const stand = structuredClone((await (await fetch(base + '/v1/scenarios/default')).json()));
    stand.strip.flow_stress_MPa = 520;
    const stored = await fetch(base + '/v1/scenarios/stand-3', { method: 'PUT', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(stand) });
    check(stored.status === 201, `PUT /v1/scenarios/stand-3 answered ${stored.status}`);
    const version = stored.headers.get('etag').replace(/"/g, '');
    const json = (body, headers = {}) => ({ status: 200, contentType: 'application/json', headers, body: JSON.stringify(body) });
    // Paging is answered by a route: the service would need more jobs than a test should make.
    let listed = 0;
    await other.route(/\/v1\/jobs\?/, (route) => {
      listed++;
      const cursor = new URL(route.request().url()).searchParams.get('cursor');
      return route.fulfill(json(cursor ? { jobs: [{ id: 'b'.repeat(32), analysis: 'map', state: 'succeeded', created_at: '2026-11-30T07:00:00Z' }] }
        : { jobs: [{ id: 'a'.repeat(32), analysis: 'sweep', state: 'running', created_at: '2026-11-30T08:00:00Z' }], next_cursor: 'c2' }));
    });
    const sent = [];
    other.on('request', (request) => { if (request.method() === 'POST' && request.url().endsWith('/v1/roll-gap')) sent.push(request.postDataJSON()); });
    await other.goto(base + '/');
    await other.waitForSelector('body[data-ready="true"]');
    check(await other.isVisible('#base-row'), 'the stored scenarios are offered');
    check(/this service/.test(await other.textContent('#jobs-title')) && (await other.$$('#job-list li')).length === 2, 'the service\'s jobs, and a button for older ones');
    await other.click('#job-list button:text("Older jobs")');
    await other.waitForFunction(() => /map/.test(document.getElementById('job-list').textContent));
    check(/sweep/.test(await other.textContent('#job-list')) && !/Older jobs/.test(await other.textContent('#job-list')), 'older jobs appended; no more pages');
    check(listed === 2, `the list was asked ${listed} times`);
    await other.selectOption('#base', 'stand-3');
    await other.waitForFunction(() => document.getElementById('f-scenario-strip-flow-stress-MPa').value === '520');
    check(/stored scenario stand-3/.test(await other.textContent('#diff-count')), 'the base is named');
    check(new RegExp(`version ${version}`).test(await other.textContent('#base-version')), 'its version (ETag) is shown');
    await other.fill('#f-scenario-strip-reduction', '0.25');
    const differ = await other.$$eval('#diff li', (all) => all.map((li) => [li.dataset.pointer, li.textContent]));
    check(differ.length === 1 && differ[0][0] === '/strip/reduction' && / 0\.15 → 0\.25$/.test(differ[0][1]), `differences from the base only: ${JSON.stringify(differ)}`);
    await other.click('#run');
    await other.waitForSelector('#plot-pressure', { timeout: 60000 });
    check(sent.length === 1 && sent[0].base === 'stand-3' && JSON.stringify(sent[0].scenario) === '{"strip":{"reduction":0.25}}', `request: ${JSON.stringify(sent)}`);
    // What the page drew is the service's answer on the stored stand: the same as the stand sent in full.
    const merged = structuredClone(stand);
    merged.strip.reduction = 0.25;
    const direct = await post('/v1/roll-gap', { scenario: merged });
    const viaBase = await post('/v1/roll-gap', { base: 'stand-3', scenario: { strip: { reduction: 0.25 } } });
    check(viaBase.status === 200 && viaBase.body.base.name === 'stand-3' && String(viaBase.body.base.version) === version, `base echo: ${JSON.stringify(viaBase.body.base)}`);
    check(JSON.stringify(viaBase.body.result) === JSON.stringify(direct.body.result), 'the stored stand computes as the stand sent in full');
    const drawn = await other.evaluate(() => Chart.getChart(document.getElementById('plot-pressure')).data.datasets
      .find((d) => d.label === 'pressure [MPa]').data.map((p) => p.y));
    equalArrays(drawn, direct.body.result.distribution.pressure_MPa, 'pressure_MPa on the stored stand');
    check(other.url().includes('base=stand-3'), 'the base is in the link');
    await shot('stored-scenario', other);
    await scenarios.close();
  });

  await test('the editor\'s stand against a stored one: the stored stand run as stored and pinned, the editor\'s drawn beside it, both the API\'s', async () => {
    await page.goto(base + '/');
    await page.waitForSelector('body[data-ready="true"]');
    await page.click('#tab-stability');
    check(await page.isVisible('#compare-row'), 'a stored stand can be compared');
    await page.selectOption('#compare-stored', 'stand-3');
    await page.fill('#f-scenario-strip-reduction', '0.25');
    await page.evaluate(() => document.getElementById('plots').replaceChildren());
    const sent = await postedDuring('/v1/stability', async () => {
      await page.click('#compare-run');
      await page.waitForFunction(() => /^done in/.test(document.getElementById('status').textContent) && document.getElementById('plot-damping'), null, { timeout: 120000 });
    });
    // The stored stand as stored (its name as base, no changes), then the editor's stand; the
    // same options for both.
    check(sent.length === 2 && sent[0].base === 'stand-3' && canon(sent[0].scenario) === '{}', `first: ${JSON.stringify(sent[0])}`);
    check(sent[1].base === undefined && sent[1].scenario.strip.reduction === 0.25 && canon(sent[1].options) === canon(sent[0].options), `then: ${JSON.stringify(sent[1])}`);
    const version = (await fetch(base + '/v1/scenarios/stand-3')).headers.get('etag').replace(/"/g, '');
    const name = await page.textContent('#pinned-name');
    check(await page.isVisible('#pinned') && name === `stored stand stand-3 (version ${version})`, `pinned: ${name}`);
    const [storedApi, currentApi] = await Promise.all(sent.map(async (b) => (await post('/v1/stability', b)).body.result.critical_speed));
    // stand-3 is stored with a flow stress of 520 MPa: another stand, another critical speed.
    check(storedApi.critical_speed_m_per_s !== currentApi.critical_speed_m_per_s, 'two different stands');
    await checkPinnedDamping(name, storedApi, currentApi);
    await shot('stability-compare-stored');
    await page.click('#unpin');
  });

  await test('a stored stand calibrated from a coil\'s measurements on the page: a new version with its posterior (If-Match)', async () => {
    await page.goto(base + '/');  // without a view in the link: nothing runs by itself
    await page.waitForSelector('body[data-ready="true"]');
    check(await page.isHidden('#calibrate-stored'), 'no calibration form for the default scenario');
    await page.selectOption('#base', 'stand-3');
    await page.waitForSelector('#calibrate-stored:not([hidden])');
    const before = await fetch(`${base}/v1/scenarios/stand-3`);
    const version = Number(before.headers.get('etag').replace(/"/g, ''));
    await page.click('#calibrate-stored summary');
    const parameters = [{ field: '/strip/flow_stress_MPa' }];
    const observations = [{ quantity: 'roll_force_kN', value: 9000, standard_uncertainty: 50 }];
    await fillRows('calibrate-stored-parameters', parameters);
    await fillRows('calibrate-stored-observations', observations);
    const sent = [];
    const listen = (request) => { if (request.method() === 'POST' && request.url().endsWith('/v1/scenarios/stand-3/calibrate')) sent.push({ headers: request.headers(), body: request.postDataJSON() }); };
    page.on('request', listen);
    await page.click('#calibrate-stored-run');
    await page.waitForFunction(() => /stored as version/.test(document.getElementById('calibrate-stored-status').textContent), null, { timeout: 60000 });
    page.off('request', listen);
    check(sent.length === 1 && sent[0].headers['if-match'] === `"${version}"`, `the page sent If-Match ${sent.length && sent[0].headers['if-match']}, the stored version is ${version}`);
    check(JSON.stringify(sent[0].body.options.observations) === JSON.stringify(observations), 'the measurements as typed');
    const after = await fetch(`${base}/v1/scenarios/stand-3`);
    check(Number(after.headers.get('etag').replace(/"/g, '')) === version + 1, `stored as version ${after.headers.get('etag')}`);
    const posterior = (await (await fetch(`${base}/v1/scenarios/stand-3/calibrate`)).json()).posterior;
    const fitted = posterior.parameters[0];
    check(fitted.field === '/strip/flow_stress_MPa' && fitted.standard_error > 0, `stored posterior: ${JSON.stringify(posterior)}`);
    check((await after.json()).strip.flow_stress_MPa === fitted.value, 'the stored stand is the posterior mean');
    // The page shows the fit and now starts from the new version.
    const cells = await page.$$eval('#plots table:first-of-type tbody tr', (rows) => rows.map((tr) => [...tr.cells].map((c) => c.dataset.value ?? c.textContent)));
    check(await page.getAttribute('#plots table:first-of-type tbody tr', 'title') === fitted.field && Number(cells[0][3]) === fitted.value && Number(cells[0][4]) === fitted.standard_error, `the fitted row: ${JSON.stringify(cells[0])}`);
    check(new RegExp(`version ${version + 1}`).test(await page.textContent('#base-version')), `base version: ${await page.textContent('#base-version')}`);
    check(Number(await page.inputValue('#f-scenario-strip-flow-stress-MPa')) === fitted.value, 'the editor shows the calibrated stand');
    await shot('calibrate-stored');
    await checkAxe();
    await page.selectOption('#base', '');
    await page.waitForSelector('#calibrate-stored[hidden]', { state: 'attached' });
  });

  await test("the editor's stand saved: a new name created (PUT, If-None-Match), its next version an edit (PATCH, If-Match); a stale save (412) says what to do", async () => {
    check(await page.isVisible('#save-row'), 'saving is offered');
    const writes = [];
    const listen = (request) => { if (['PUT', 'PATCH'].includes(request.method()) && /\/v1\/scenarios\/stand-9$/.test(request.url())) writes.push({ method: request.method(), headers: request.headers(), body: request.postDataJSON() }); };
    page.on('request', listen);
    const saved = (version) => page.waitForFunction((v) => document.getElementById('save-status').textContent === `saved as stand-9, version ${v}`, version, { timeout: 30000 });
    await page.fill('#f-scenario-strip-reduction', '0.22');
    await page.fill('#save-name', 'stand-9');
    await page.click('#save');
    await saved(1);
    check(writes.length === 1 && writes[0].method === 'PUT' && writes[0].headers['if-none-match'] === '*', `created only: ${JSON.stringify(writes.map((w) => [w.method, w.headers['if-none-match']]))}`);
    // What is stored is the stand the editor showed: the complete scenario the API echoes for its patch.
    const stored = await (await fetch(`${base}/v1/scenarios/stand-9`)).json();
    const echo = (await post('/v1/roll-gap', { scenario: { strip: { reduction: 0.22 } }, options: { distributions: false } })).body.scenario;
    check(canon(stored) === canon(echo), 'the stored stand is the editor\'s');
    check(await page.inputValue('#base') === 'stand-9' && /version 1$/.test(await page.textContent('#base-version')), 'the editor now starts from it');
    check(await page.$$eval('#base option', (all) => all.filter((o) => o.value === 'stand-9').length) === 1, 'the stored list has it once');
    // An edit of it: the changes as a merge patch onto the version loaded.
    await page.fill('#f-scenario-rolls-speed-m-per-s', '18');
    await page.click('#save');
    await saved(2);
    check(writes.length === 2 && writes[1].method === 'PATCH' && writes[1].headers['if-match'] === '"1"' && canon(writes[1].body) === canon({ rolls: { speed_m_per_s: 18 } }), `the edit: ${JSON.stringify(writes[1])}`);
    const second = await (await fetch(`${base}/v1/scenarios/stand-9`)).json();
    check(second.rolls.speed_m_per_s === 18 && second.strip.reduction === 0.22, 'version 2 has both');
    // Someone else edits version 2 meanwhile: the page's save is refused and says what to do.
    const theirs = await fetch(`${base}/v1/scenarios/stand-9`, { method: 'PATCH', headers: { 'Content-Type': 'application/json', 'If-Match': '"2"' }, body: JSON.stringify({ strip: { flow_stress_MPa: 610 } }) });
    check(theirs.status === 200, `their edit: ${theirs.status}`);
    await page.fill('#f-scenario-rolls-speed-m-per-s', '19');
    expected412 = 1;
    await page.click('#save');
    await page.waitForSelector('#problem:not([hidden]) #save-rebase');
    const problem = await page.textContent('#problem');
    check(/changed meanwhile/.test(problem) && /version 2/.test(problem) && /412/.test(problem), `the conflict: ${problem}`);
    check((await (await fetch(`${base}/v1/scenarios/stand-9`)).json()).strip.flow_stress_MPa === 610, 'their edit is kept');
    await page.click('#save-rebase');
    await page.waitForFunction(() => /version 3$/.test(document.getElementById('base-version').textContent));
    check(await page.inputValue('#f-scenario-strip-flow-stress-MPa') === '610' && await page.inputValue('#f-scenario-rolls-speed-m-per-s') === '19', 'their change and mine in the editor');
    await page.click('#save');
    await saved(4);
    const fourth = await (await fetch(`${base}/v1/scenarios/stand-9`)).json();
    check(fourth.strip.flow_stress_MPa === 610 && fourth.rolls.speed_m_per_s === 19, 'version 4 has both edits');
    // A new name that is taken: refused, the stand there untouched.
    const taken = (await fetch(`${base}/v1/scenarios/stand-3`)).headers.get('etag');
    await page.fill('#save-name', 'stand-3');
    expected412 = 1;
    await page.click('#save');
    await page.waitForFunction(() => /exists/.test(document.getElementById('problem').textContent));
    check((await fetch(`${base}/v1/scenarios/stand-3`)).headers.get('etag') === taken, 'stand-3 untouched');
    page.off('request', listen);
    await shot('save-stand');
    await checkAxe();
    await page.selectOption('#base', '');
    await page.click('#reset');
  });

  await test('an analysis the document offers without a view of the page still runs (its headline numbers)', async () => {
    const rows = await documentAnalyses();
    const hidden = rows.find((r) => !r.on_page);
    if (!hidden) { console.log('  (every analysis is on the page: nothing to check)'); return; }
    const offered = await browser.newContext({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
    const other = watch(await offered.newPage());
    // The document as a service would serve it with that row on the page.
    await other.route(/\/openapi\.json$/, async (route) => {
      const doc = await (await route.fetch()).json();
      doc['x-rollgap-analyses'].find((r) => r.name === hidden.name).on_page = true;
      return route.fulfill({ status: 200, contentType: 'application/json', body: JSON.stringify(doc) });
    });
    await other.goto(base + '/');
    await other.waitForSelector('body[data-ready="true"]');
    check(await other.textContent(`#tab-${hidden.name}`) === hidden.label, 'its tab, labelled from the document');
    await other.click(`#tab-${hidden.name}`);
    await other.click('#run');
    await other.waitForSelector('#headline table', { timeout: 120000 });
    check((await other.textContent('#headline caption')).startsWith(hidden.label), `headline: ${await other.textContent('#headline caption')}`);
    check(await other.isVisible('#download-json'), 'the JSON download is offered');
    check(await other.isVisible('#download-csv') === hidden.csv, 'the CSV download is offered iff the row has CSV');
    await shot('without-view', other);
    await offered.close();
  });

  // The mill view: a two-stand mill (critical speeds in ~0.1 s), its numbers read back from the
  // page's text (display rounding only) and compared with the API's answer to the request the
  // page sent.
  // A number the page shows to 4 significant digits (views.js fmt) is the API's, rounded.
  const near = (shown, exact, what) => check(Number.isFinite(shown) && Math.abs(shown - exact) <= 5e-4 * Math.abs(exact) * (1 + 1e-9), `${what}: the page shows ${shown}, the API gave ${exact}`);
  const headlineTable = () => page.$$eval('#headline tbody tr', (rows) => Object.fromEntries(rows.map((tr) => [tr.cells[0].textContent, tr.cells[1].textContent])));
  const twoStands = { entry_thickness_mm: 2.25, exit_thickness_mm: [1.88, 1.6], spans: { length_m: [5], tension_MPa: [60] }, stands: [{}, {}] };
  const millInputs = async (prefix) => page.$$eval(`[data-pointer^="${prefix}"]`, (all) => all.map((i) => i.value));
  await test('mill view: the stands, the three critical speeds and the participation are the API\'s numbers', async () => {
    const row = (await documentAnalyses()).find((r) => r.name === 'tandem');
    check(row && row.on_page && row.subject === 'tandem', `the tandem row: ${JSON.stringify(row)}`);
    await page.click('#tab-tandem');
    check(await page.isVisible('#mill-editor') && await page.isHidden('#editor'), 'the mill editor replaces the scenario editor');
    // The default mill, from the document's Tandem defaults.
    const defaults = (await (await fetch(base + '/openapi.json')).json()).components.schemas.Tandem.properties;
    check(await page.inputValue('#f-tandem-stands') === String(defaults.exit_thickness_mm.default.length), 'the default number of stands');
    equalArrays((await millInputs('/tandem/exit_thickness_mm/')).map(Number), defaults.exit_thickness_mm.default, 'the default pass schedule');
    equalArrays((await millInputs('/tandem/spans/tension_MPa/')).map(Number), defaults.spans.properties.tension_MPa.default, 'the default span tensions');
    check(Number(await page.inputValue('#f-tandem-speed-m-per-s')) === defaults.speed_m_per_s.default, 'the default mill speed');
    await page.fill('#f-tandem-stands', '2');
    check((await millInputs('/tandem/exit_thickness_mm/')).length === 2 && (await millInputs('/tandem/spans/length_m/')).length === 1, 'two stands, one span');
    await page.fill('#f-tandem-entry-thickness-mm', '2.25');
    await page.fill('#f-tandem-exit-thickness-mm-0', '1.88');
    await page.fill('#f-tandem-exit-thickness-mm-1', '1.6');
    await page.fill('#f-tandem-spans-length-m-0', '5');
    await page.fill('#f-tandem-spans-tension-MPa-0', '60');
    if (await page.$('#f-options-critical-speed')) await page.selectOption('#f-options-critical-speed', 'true');
    const sent = await postedDuring(row.path, () => runAndWait('participation'));
    check(sent.length === 1 && canon(sent[0].tandem) === canon(twoStands), `the page sent: ${JSON.stringify(sent)}`);
    const answer = await post(row.path, sent[0]);
    check(answer.status === 200, `the API answered ${answer.status}`);
    const r = answer.body.result;
    const stands = r.steady_state.stands;
    const c = r.critical_speeds;
    check(c && c.headline, 'this mill has a headline critical speed');
    const crossing = c[c.headline];
    // The stands in a row: roll speed, force, the tensions between them, the marked stands.
    const shown = await page.$$eval('#mill-row .mill-stand', (items) => items.map((li) => ({
      stand: Number(li.dataset.stand), name: li.querySelector('.mill-name').textContent,
      roll: Number(li.querySelector('[data-quantity="roll_speed"]').textContent), force: Number(li.querySelector('[data-quantity="force"]').textContent),
      flags: [...li.querySelectorAll('.mill-flag')].map((f) => f.textContent) })));
    check(shown.length === stands.length, `${shown.length} stands shown, the API has ${stands.length}`);
    shown.forEach((s, i) => {
      check(s.stand === stands[i].stand && s.name === `Stand ${stands[i].stand}`, `stand ${i}: ${s.name}`);
      near(s.roll, stands[i].roll_speed_m_per_s, `stand ${s.stand} roll speed [m/s]`);
      near(s.force, stands[i].force_kN, `stand ${s.stand} roll force [kN]`);
    });
    const tensions = await page.$$eval('#mill-row .mill-span [data-quantity="tension"]', (all) => all.map((t) => Number(t.textContent)));
    check(tensions.length === stands.length - 1, `${tensions.length} interstand tensions shown`);
    tensions.forEach((t, i) => near(t, stands[i].front_tension_MPa, `tension between stands ${i + 1} and ${i + 2} [MPa]`));
    const flagged = (word) => shown.filter((s) => s.flags.some((f) => f.includes(`${word} stand`))).map((s) => s.stand);
    equalArrays(flagged('moving'), [crossing.moving_stand], 'the stand marked moving');
    equalArrays(flagged('feeding'), [crossing.feeding_stand], 'the stand marked feeding');
    // The headline figures.
    const headline = await headlineTable();
    near(Number(headline['headline critical speed']), c.critical_speed_m_per_s, 'headline critical speed [m/s]');
    check(headline['moving stand'] === `stand ${crossing.moving_stand}` && headline['feeding stand'] === `stand ${crossing.feeding_stand}`, `moving / feeding: ${headline['moving stand']} / ${headline['feeding stand']}`);
    near(Number(headline["mill speed (the last stand's roll speed)"]), answer.body.tandem.speed_m_per_s, 'mill speed');
    // The three critical speeds on one axis: the headline, those outside the model's range, the mill speed.
    const chart = await chartData('critical-speeds');
    const found = ['frozen', 'delay_independent', 'nominal_delay'].filter((k) => c[k].speed_m_per_s !== null);
    const valid = found.filter((k) => c[k].validity.valid);
    check(found.length > valid.length, 'this mill has a crossing outside the model\'s range');
    equalArrays(dataset(chart, 'headline critical speed').map((p) => p.x), [c.critical_speed_m_per_s], 'the headline marker');
    equalArrays(dataset(chart, "critical speed inside the model's range").map((p) => p.x).sort(), valid.map((k) => c[k].speed_m_per_s).sort(), 'crossings inside the range');
    equalArrays(dataset(chart, "critical speed outside the model's range").map((p) => p.x).sort(), found.filter((k) => !valid.includes(k)).map((k) => c[k].speed_m_per_s).sort(), 'crossings outside the range');
    check(dataset(chart, "mill speed (the last stand's roll speed)")[0].x === answer.body.tandem.speed_m_per_s, 'the mill speed marker');
    const table = await page.$$eval('#critical-speeds-table tbody tr', (rows) => rows.map((tr) => ({ kind: tr.dataset.kind, cells: [...tr.cells].map((td) => td.textContent) })));
    for (const k of found) {
      const line = table.find((t) => t.kind === k);
      near(Number(line.cells[1]), c[k].speed_m_per_s, `${k} critical speed [m/s]`);
      check(line.cells[7].startsWith(c[k].validity.valid ? "inside the model's range" : "outside the model's range"), `${k}: ${line.cells[7]}`);
      check(line.cells[0].endsWith('headline') === (k === c.headline), `${k}: ${line.cells[0]}`);
    }
    // The participation of the headline crossing's root, by stand.
    const bars = await chartData('participation');
    equalArrays(bars.labels, crossing.participation.map((_, i) => `stand ${i + 1}`), 'participation bars');
    equalArrays(bars.datasets[0].data, crossing.participation, 'participation');
    await shot('tandem');
    await checkAxe();
    // Without the critical speeds: the rightmost root's stands and participation.
    if (await page.$('#f-options-critical-speed')) {
      await page.selectOption('#f-options-critical-speed', 'false');
      await runAndWait('participation');
      const root = (await post(row.path, { tandem: twoStands, options: { critical_speed: false } })).body.result.stability.rightmost_root;
      equalArrays((await chartData('participation')).datasets[0].data, root.participation, 'participation of the rightmost root');
      const without = await headlineTable();
      check(without['headline critical speed'] === 'not asked' && without['moving stand'] === `stand ${root.moving_stand}` && without['feeding stand'] === `stand ${root.feeding_stand}`, `without critical speeds: ${JSON.stringify(without)}`);
      check(await page.$('#plot-critical-speeds') === null, 'no critical speeds drawn when not asked');
      await page.selectOption('#f-options-critical-speed', '');
    }
  });

  // The same two-stand mill, its answer kept for the tests after this one.
  let millRequest = null;
  let millAnswer = null;
  const millKinds = { frozen: 'frozen-mill', delay_independent: 'delay-independent', nominal_delay: 'nominal-delay' };
  const scaleTitles = (id) => page.evaluate((canvasId) => Object.fromEntries(Object.entries(Chart.getChart(document.getElementById(canvasId)).options.scales)
    .map(([axis, scale]) => [axis, scale.title.text])), `plot-${id}`);
  const sweepDone = (timeout = 60000) => page.waitForSelector('#plot-speed-sweep[data-state="done"]', { timeout });
  await test('mill view: ρ and the growth rate against mill speed (its speed swept as a job) with the three critical speeds marked', async () => {
    const jobs = [];
    const tandems = [];
    const listen = (request) => {
      if (request.method() !== 'POST') return;
      if (request.url() === `${base}/v1/jobs`) jobs.push(request.postDataJSON());
      if (request.url() === `${base}/v1/tandem`) tandems.push(request.postDataJSON());
    };
    page.on('request', listen);
    await runAndWait('speed-sweep');
    await sweepDone();
    page.off('request', listen);
    check(tandems.length === 1 && jobs.length === 1, `the page posted ${tandems.length} tandem requests and ${jobs.length} jobs`);
    const job = jobs[0];
    check(job.analysis === 'tandem_sweep' && job.options.parameter === '/speed_m_per_s' && job.options.quantity === 'stability', `the job: ${JSON.stringify(job.options)}`);
    millRequest = tandems[0];
    const answer = await post('/v1/tandem', millRequest);
    check(answer.status === 200, `the API answered ${answer.status}`);
    millAnswer = answer.body;
    check(canon(job.tandem) === canon(millAnswer.tandem), 'the speeds swept are of the mill the answer echoes');
    const { analysis, ...sweepBody } = job;
    const sweep = await post('/v1/tandem/sweeps', sweepBody);
    check(sweep.status === 200 && sweep.body.result.unit === 'm/s', `the sweep answered ${sweep.status}`);
    const api = sweep.body.result.points;
    const c = millAnswer.result.critical_speeds;
    const found = Object.keys(millKinds).filter((k) => c[k] && c[k].speed_m_per_s !== null);
    check(job.options.range.from < Math.min(...found.map((k) => c[k].speed_m_per_s)) && job.options.range.to > Math.max(...found.map((k) => c[k].speed_m_per_s)), `the speeds ${JSON.stringify(job.options.range)} span the critical speeds`);
    check(api.some((p) => p.regenerative_margin === null) && api.some((p) => p.in_model_range === false), 'this range has speeds without ρ (the frozen mill unstable) and roots outside the model\'s range');
    const chart = await chartData('speed-sweep');
    const rho = dataset(chart, 'regenerative margin ρ [-]');
    equalArrays(rho.map((p) => p.x), api.map((p) => p.value_m_per_s), 'mill speeds');
    equalArrays(rho.map((p) => p.y), api.map((p) => p.regenerative_margin), 'ρ');
    equalArrays(dataset(chart, 'growth rate of the rightmost root [1/s]').map((p) => p.y), api.map((p) => p.growth_rate_per_s), 'growth rate');
    equalArrays(dataset(chart, "rightmost root outside the model's range").map((p) => p.x), api.filter((p) => p.in_model_range === false).map((p) => p.value_m_per_s), 'roots outside the range');
    // The three critical speeds of the answer, the headline marked as such.
    for (const k of found) {
      const marked = chart.datasets.filter((d) => d.label.startsWith(`${millKinds[k]} critical speed`));
      check(marked.length === 1, `one line for the ${k} critical speed: ${chart.datasets.map((d) => d.label).join(', ')}`);
      equalArrays(marked[0].data.map((p) => p.x), [c[k].speed_m_per_s, c[k].speed_m_per_s], `${k} critical speed line`);
      check(marked[0].label.includes('— headline') === (k === c.headline), `${k}: ${marked[0].label}`);
      check(marked[0].label.includes("outside the model's range") === !c[k].validity.valid, `${k}: ${marked[0].label}`);
    }
    equalArrays(datasetStarting(chart, 'mill speed').data.map((p) => p.x), [millAnswer.tandem.speed_m_per_s, millAnswer.tandem.speed_m_per_s], 'the mill speed line');
    const titles = await scaleTitles('speed-sweep');
    check(titles.x === "mill speed, the last stand's roll speed [m/s]" && titles.y === 'regenerative margin ρ [-]' && titles.y2 === 'growth rate of the rightmost root [1/s]', `axes: ${JSON.stringify(titles)}`);
    check(/job succeeded/.test(await page.textContent('#speed-sweep-status')), 'the sweep\'s status');
    await shot('tandem-speed-sweep');
    // Drawn again with fewer speeds, held running with two of them done: those two drawn, the others not yet.
    await page.fill('#speed-sweep-count', '7');
    const seven = { ...sweepBody, options: { ...sweepBody.options, range: { ...sweepBody.options.range, count: 7 } } };
    const few = (await post('/v1/tandem/sweeps', seven)).body.result.points;
    const release = await holdJob((j) => ({ ...j, state: 'running', result: undefined, progress: 0.3, points_total: 7, points_done: 2,
      partial_result: { partial: true, points_total: 7, points_done: 2, points: [1, 4].map((i) => ({ index: i, point: few[i] })) } }));
    try {
      await page.click('#speed-sweep-run');
      await page.waitForFunction(() => /2 of 7/.test(document.getElementById('speed-sweep-status').textContent), null, { timeout: 30000 });
      const running = dataset(await chartData('speed-sweep'), 'growth rate of the rightmost root [1/s]');
      // The speeds not computed yet at the page's own values of the range (the service's are rounded to 12 digits).
      check(running.length === few.length, `${running.length} speeds drawn while running, the API has ${few.length}`);
      running.forEach((p, i) => check([1, 4].includes(i) ? p.x === few[i].value_m_per_s : Math.abs(p.x - few[i].value_m_per_s) <= 1e-9 * few[i].value_m_per_s, `speed ${i} while running: ${p.x}, the API ${few[i].value_m_per_s}`));
      equalArrays(running.map((p) => p.y), few.map((p, i) => ([1, 4].includes(i) ? p.growth_rate_per_s : null)), 'the finished speeds while running');
    } finally {
      await release();
    }
    await sweepDone();
    equalArrays(dataset(await chartData('speed-sweep'), 'growth rate of the rightmost root [1/s]').map((p) => p.y), few.map((p) => p.growth_rate_per_s), 'growth rate, 7 speeds');
  });

  await test("mill view: ρ's factors per span, the span carrying the most named, and each crossing's chatter type are the API's", async () => {
    check(millAnswer, 'the mill answer of the test before');
    const s = millAnswer.result.stability;
    const factors = s.margin_factors;
    check(Array.isArray(factors) && factors.length === 1, `factors: ${JSON.stringify(factors)}`);
    const rows = await page.$$eval('#margin-factors-table tbody tr', (all) => all.map((tr) => ({ span: tr.dataset.span, cells: [...tr.cells].map((td) => td.dataset.value ?? td.textContent) })));
    check(rows.length === factors.length, `${rows.length} rows, the API has ${factors.length} spans`);
    const header = await page.$$eval('#margin-factors-table thead th', (all) => all.map((th) => th.textContent));
    check(/\[kN\/mm\]$/.test(header[4]) && /\[1\/s\]$/.test(header[5]) && /\[µm\/kN\]$/.test(header[6]), `units in the header: ${header.join(' | ')}`);
    factors.forEach((f, i) => {
      check(rows[i].span === String(f.span) && rows[i].cells[0] === `stand ${f.span} → ${f.span + 1}`, `row ${i}: ${rows[i].cells[0]}`);
      const keys = ['worst_input_share', 'tension_loop_gain', 'thickness_gain', 'bite_force_gain_kN_per_mm', 'bite_entry_speed_gain_per_s', 'compliance_um_per_kN'];
      keys.forEach((key, j) => {
        if (f[key] === null) check(rows[i].cells[j + 1].startsWith('—'), `${key}: ${rows[i].cells[j + 1]}`);
        else check(Number(rows[i].cells[j + 1]) === f[key], `${key}: the page has ${rows[i].cells[j + 1]}, the API ${f[key]}`);
      });
    });
    const top = factors.reduce((a, b) => (b.worst_input_share > a.worst_input_share ? b : a));
    const sentence = await page.textContent('#margin-sentence');
    check(await page.getAttribute('#margin-sentence', 'data-span') === String(top.span) && sentence.includes(`from stand ${top.span} to stand ${top.span + 1}`), `sentence: ${sentence}`);
    near(Number(/ρ = ([0-9.e+-]+)/.exec(sentence)[1]), s.regenerative_margin, 'ρ in the sentence');
    check(await page.getAttribute('#margin-validity', 'data-valid') === String(s.margin_validity.valid), 'the peak\'s range');
    check((await page.textContent('#margin-validity')).includes(s.margin_validity.valid ? "inside the model's range" : "outside the model's range"), 'the peak\'s range in words');
    const c = millAnswer.result.critical_speeds;
    const table = await page.$$eval('#critical-speeds-table tbody tr', (all) => all.map((tr) => ({ kind: tr.dataset.kind, cells: [...tr.cells].map((td) => td.textContent) })));
    const header2 = await page.$$eval('#critical-speeds-table thead th', (all) => all.map((th) => th.textContent));
    check(header2[5] === 'chatter band' && header2[6] === 'chatter type', `columns: ${header2.join(' | ')}`);
    for (const k of Object.keys(millKinds).filter((kind) => c[kind])) {
      const line = table.find((t) => t.kind === k);
      check(line.cells[5] === (c[k].band ? chatterNames[c[k].band] : '—') && line.cells[6] === (c[k].chatter_type ? chatterNames[c[k].chatter_type] : '—'), `${k}: band ${line.cells[5]}, type ${line.cells[6]}; the API ${c[k].band}, ${c[k].chatter_type}`);
    }
    check(Object.keys(millKinds).some((k) => c[k] && c[k].band && c[k].chatter_type && c[k].band !== c[k].chatter_type), 'this mill has a crossing whose type differs from its band');
    await shot('tandem-margin-factors');
  });

  await test('mill view: the time series of each stand (gap, force, tension) and how the run ended are the API\'s', async () => {
    await page.selectOption('#f-options-time-series', 'true');
    await page.fill('#f-options-window-s', '0.1');
    await page.fill('#f-options-time-series-points', '80');
    const sent = await postedDuring('/v1/tandem', () => runAndWait('time-tension'));
    check(sent.length === 1 && sent[0].options.time_series === true, `the page sent: ${JSON.stringify(sent.map((b) => b.options))}`);
    const ts = (await post('/v1/tandem', sent[0])).body.result.time_series;
    check(ts && ts.stands.length === 2, 'the API gave two stands\' series');
    const gap = await chartData('time-gap');
    const force = await chartData('time-force');
    ts.stands.forEach((s) => {
      const g = dataset(gap, `stand ${s.stand}`);
      equalArrays(g.map((p) => p.x), s.series.time_s, `stand ${s.stand} time`);
      equalArrays(g.map((p) => p.y), s.series.gap_change_um, `stand ${s.stand} gap change`);
      equalArrays(dataset(force, `stand ${s.stand}`).map((p) => p.y), s.series.force_kN, `stand ${s.stand} force`);
    });
    const tension = await chartData('time-tension');
    equalArrays(dataset(tension, 'entry span (stand 1 back tension)').map((p) => p.y), ts.stands[0].series.back_tension_MPa, 'entry tension');
    equalArrays(dataset(tension, 'span stand 1 → 2').map((p) => p.y), ts.stands[0].series.front_tension_MPa, 'interstand tension');
    equalArrays(dataset(tension, 'exit span (stand 2 front tension)').map((p) => p.y), ts.stands[1].series.front_tension_MPa, 'exit tension');
    for (const [id, y] of [['time-gap', 'roll gap change [µm]'], ['time-force', 'roll force [kN]'], ['time-tension', 'strip tension [MPa]']]) {
      const titles = await scaleTitles(id);
      check(titles.x === 'time [s]' && titles.y === y, `${id} axes: ${JSON.stringify(titles)}`);
    }
    check(await page.getAttribute('#time-series-state', 'data-status') === ts.status, `state: ${await page.textContent('#time-series-state')}, the API ${ts.status}`);
    near(Number(/at ([0-9.e+-]+) s/.exec(await page.textContent('#time-series-state'))[1]), ts.end_time_s, 'end time');
    await shot('tandem-time-series');
    await sweepDone();  // the speed sweep of this run finished: nothing left running for the next test
  });

  await test('mill view: a run that ends on a slack span says so, with the span and the time the API names', async () => {
    // A harder kick at a higher speed: the entry span goes slack before the window ends.
    await page.fill('#f-tandem-speed-m-per-s', '20');
    await page.fill('#f-options-kick-um', '10');
    await page.fill('#f-options-window-s', '1');
    await page.selectOption('#f-options-critical-speed', 'false');
    const sent = await postedDuring('/v1/tandem', () => runAndWait('time-tension'));
    const ts = (await post('/v1/tandem', sent[0])).body.result.time_series;
    check(ts.status === 'slack_span', `the API's run ended ${ts.status}: choose a case with a slack span`);
    const state = await page.textContent('#time-series-state');
    check(await page.getAttribute('#time-series-state', 'data-status') === ts.status && state.includes(ts.message), `state: ${state}; the API: ${ts.status}, ${ts.message}`);
    if (ts.stand !== null) check(state.includes(`stand ${ts.stand}`), `the stand named: ${state}`);
    if (ts.span !== null) {
      const span = ts.span === 0 ? 'the entry span' : ts.span === ts.stands.length ? 'the exit span' : `the span from stand ${ts.span} to stand ${ts.span + 1}`;
      check(state.includes(span), `the span named (${span}): ${state}`);
    }
    near(Number(/at ([0-9.e+-]+) s/.exec(state)[1]), ts.end_time_s, 'the time it ended');
    equalArrays(dataset(await chartData('time-gap'), 'stand 1').map((p) => p.x), ts.stands[0].series.time_s, 'the series up to the end');
    await shot('tandem-time-series-ended');
    for (const id of ['#f-options-kick-um', '#f-options-window-s', '#f-options-time-series-points']) await page.fill(id, '');
    await page.selectOption('#f-options-time-series', '');
    await page.selectOption('#f-options-critical-speed', '');
    await page.fill('#f-tandem-speed-m-per-s', '15');
  });

  await test("mill speed limit: each stand's limits and the mill's chatter limit on the mill-speed axis, the binding stand marked, are the API's", async () => {
    const row = (await documentAnalyses()).find((r) => r.name === 'tandem_speed_limit');
    check(row && row.on_page && row.subject === 'tandem', `the tandem_speed_limit row: ${JSON.stringify(row)}`);
    await page.click('#tab-tandem_speed_limit');
    check(await page.isVisible('#mill-editor'), 'a mill analysis: the mill editor');
    await page.fill('#f-options-max-roll-force-kN', '11500');
    await page.fill('#f-options-max-power-kW', '5000');
    await page.fill('#f-options-chatter-margin', '0.05');
    const sent = await postedDuring(row.path, () => runAndWait('speed-limits'));
    check(sent.length === 1 && canon(sent[0].tandem) === canon(twoStands) && sent[0].options.max_roll_force_kN === 11500 && sent[0].options.max_power_kW === 5000, `the page sent: ${JSON.stringify(sent)}`);
    const api = (await post(row.path, sent[0])).body.result;
    check(api.status === 'ok' && api.binding_limit && api.binding_stand, `the API's answer: ${api.status}, binding ${api.binding_limit} of stand ${api.binding_stand}`);
    const chart = await chartData('speed-limits');
    const names = { force: 'roll force', power: 'motor power', chatter: 'chatter' };
    // One bar per limit and stand, spanning the speeds its own answer gives; the binding ones named.
    const limits = api.limits.filter((x) => x.limit !== 'steady_state');
    check(limits.filter((l) => l.limit === 'force').length === 2 && limits.filter((l) => l.limit === 'power').length === 2, 'a force and a power limit per stand');
    for (const l of limits) {
      const binding = (l.limit === api.binding_limit && l.stand === api.binding_stand) || (l.limit === api.binding_min && l.stand === api.binding_min_stand);
      const label = `${names[l.limit]} · stand ${l.stand} permits${binding ? ' (binding)' : ''}`;
      if (l.lower_speed_m_per_s === null && l.upper_speed_m_per_s === null && !l.met_at_operating) continue;
      const bar = dataset(chart, label);
      check(bar.length === 2, `a bar "${label}"`);
      if (l.lower_speed_m_per_s !== null) check(bar[0].x === l.lower_speed_m_per_s, `${label} from ${bar[0].x}, the API ${l.lower_speed_m_per_s}`);
      if (l.upper_speed_m_per_s !== null) check(bar[1].x === l.upper_speed_m_per_s, `${label} to ${bar[1].x}, the API ${l.upper_speed_m_per_s}`);
    }
    const window = dataset(chart, 'permitted window');
    check(window[0].x === api.window_min_m_per_s && window[1].x === api.window_max_m_per_s, `window ${JSON.stringify(window)}`);
    check(dataset(chart, 'advised speed')[0].x === api.advised_speed_m_per_s, 'the advised speed line');
    const headline = await headlineTable();
    check(headline.answer === api.summary, `the answer: ${headline.answer}`);
    check(headline['binding limit'] === `${names[api.binding_limit]} of stand ${api.binding_stand}`, `binding: ${headline['binding limit']}`);
    near(Number(headline['advised mill speed']), api.advised_speed_m_per_s, 'advised mill speed [m/s]');
    // what to change: the API's three largest gains, fields of the tandem document
    const gains = api.what_to_change.changes.filter((x) => x.speed_gain_m_per_s !== null).slice(0, 3);
    const shown = Object.keys(headline).filter((k) => k.startsWith('to run faster: '));
    check(gains.length > 0 && shown.length === gains.length, `what to change: ${JSON.stringify(shown)} for ${gains.length} gains`);
    // Each named by the Tandem document's title, with the stand or span it belongs to, its
    // pointer beside it ("Lubricant viscosity of stand 2", "Interstand tension between stands 1 and 2").
    const doc = await (await fetch(base + '/openapi.json')).json();
    const tandemTitle = (pointer) => pointer.split('/').slice(1).reduce((node, key) => {
      if (/^\d+$/.test(key)) {
        const item = node.items && node.items.$ref ? doc.components.schemas[node.items.$ref.split('/').pop()] : node.items;
        return item && item.properties ? item : node;
      }
      return node.properties[key];
    }, doc.components.schemas.Tandem).title;
    gains.forEach((x, i) => {
      const stand = /^\/stands\/(\d+)\//.exec(x.field) || /^\/exit_thickness_mm\/(\d+)$/.exec(x.field);
      const span = /^\/spans\/[^/]+\/(\d+)$/.exec(x.field);
      const where = stand ? ` of stand ${Number(stand[1]) + 1}` : span ? ` between stands ${Number(span[1]) + 1} and ${Number(span[1]) + 2}` : '';
      const title = tandemTitle(x.field);
      check(title, `the document names ${x.field}`);
      check(shown[i].startsWith(`to run faster: ${x.direction} ${`${title}${where}`.toLowerCase()} (${x.field}) by `), `row ${i}: ${shown[i]}, the API ${x.direction} ${x.field}`);
      near(Number(headline[shown[i]]), x.speed_gain_m_per_s, `${x.field}'s gain [m/s]`);
    });
    check(chart.datasets.every((d) => !d.label.startsWith('critical speed:')), 'no uncertainty band without posteriors');
    // Stand 1's viscosity known to ±2 µPa·s, stand 2 exactly (null): a JSON list, one entry per
    // stand. The chatter lane carries the band from the 95 % lower bound to the mean, and the
    // headline the σ and the bound, the numbers the API gives.
    await page.fill('#f-options-posteriors', JSON.stringify([{ parameters: [{ field: '/lubricant/viscosity_Pa_s', value: 0.00055, standard_error: 0.000002 }] }, null]));
    const withPosteriors = await postedDuring(row.path, () => runAndWait('speed-limits'));
    check(Array.isArray(withPosteriors[0].options.posteriors) && withPosteriors[0].options.posteriors.length === 2, `the page sent posteriors: ${JSON.stringify(withPosteriors[0].options.posteriors)}`);
    const u = (await post(row.path, withPosteriors[0])).body.result.uncertainty;
    check(u && u.propagated && u.standard_deviation_m_per_s > 0, `the API's uncertainty: ${JSON.stringify(u)}`);
    const band = (await chartData('speed-limits')).datasets.find((d) => d.label.startsWith('critical speed:'));
    check(band && band.data[0].x === u.lower_bound_m_per_s && band.data[1].x === u.critical_speed_m_per_s, `band ${JSON.stringify(band && band.data)}, the API ${u.lower_bound_m_per_s} to ${u.critical_speed_m_per_s}`);
    const banded = await headlineTable();
    near(Number(banded['its standard deviation']), u.standard_deviation_m_per_s, 'σ [m/s]');
    near(Number(banded['its lower bound']), u.lower_bound_m_per_s, 'lower bound [m/s]');
    await shot('tandem-speed-limit');
    await checkAxe();
    for (const id of ['#f-options-max-roll-force-kN', '#f-options-max-power-kW', '#f-options-chatter-margin', '#f-options-posteriors']) await page.fill(id, '');
    await page.click('#tab-tandem');
  });

  await test('mill view: a 422 is shown at the mill input its pointer names', async () => {
    await page.fill('#f-tandem-exit-thickness-mm-1', '1.9');  // thicker than what stand 1 delivers
    expected422 = 1;
    const sent = await postedDuring('/v1/tandem', async () => {
      await page.click('#run');
      await page.waitForSelector('#f-tandem-exit-thickness-mm-1-error:not([hidden])', { timeout: 30000 });
    });
    const problem = await post('/v1/tandem', sent[0]);
    check(problem.status === 422 && problem.body.errors.length === 1 && problem.body.errors[0].pointer === '/tandem/exit_thickness_mm/1', `the API: ${JSON.stringify(problem.body)}`);
    const message = await page.textContent('#f-tandem-exit-thickness-mm-1-error');
    check(message.startsWith(problem.body.errors[0].detail), `message at the input: ${message}`);
    check(await page.getAttribute('#f-tandem-exit-thickness-mm-1', 'aria-invalid') === 'true', 'the input is marked invalid');
    check(await page.getAttribute('#f-tandem-exit-thickness-mm-0', 'aria-invalid') === null, 'stand 1\'s input is not');
    check(await page.evaluate(() => document.activeElement.id) === 'f-tandem-exit-thickness-mm-1', 'focus moves to the input');
    check((await page.textContent('#problem')).includes('/tandem/exit_thickness_mm/1'), 'the problem names the field');
    await shot('tandem-problem');
    await page.fill('#f-tandem-exit-thickness-mm-1', '1.6');
  });

  await test('mill editor: the mill saved under a name (PUT), a stored mill loaded; the requests name it as base', async () => {
    check(await page.isVisible('#mill-base-row') && await page.isVisible('#mill-save-row'), 'the stored mills are offered');
    // A mill stored by someone else meanwhile.
    const other = { entry_thickness_mm: 2.25, exit_thickness_mm: [1.9, 1.55], spans: { length_m: [4], tension_MPa: [70] }, stands: [{}, {}] };
    const put = await fetch(`${base}/v1/mills/line-b`, { method: 'PUT', headers: { 'Content-Type': 'application/json', 'If-None-Match': '*' }, body: JSON.stringify(other) });
    check(put.status === 201, `PUT /v1/mills/line-b answered ${put.status}`);
    // Save the two-stand mill the editor shows, with a stand of its own.
    await page.fill('#f-tandem-stands-1', '{"lubricant": {"viscosity_Pa_s": 0.0007}}');
    const shown = await page.evaluate(() => document.getElementById('f-tandem-stands-1').value);
    check(/0\.0007/.test(shown), 'the stand patch is in the editor');
    await page.fill('#mill-save-name', 'line-2w');
    const puts = [];
    const listen = (request) => { if (request.method() === 'PUT' && request.url().endsWith('/v1/mills/line-2w')) puts.push({ headers: request.headers(), body: request.postDataJSON() }); };
    page.on('request', listen);
    await page.click('#mill-save');
    await page.waitForFunction(() => /saved as line-2w/.test(document.getElementById('mill-save-status').textContent), null, { timeout: 30000 });
    check(puts.length === 1 && puts[0].headers['if-none-match'] === '*', `a new name is created only: ${JSON.stringify(puts.map((p) => p.headers))}`);
    const stored = await fetch(`${base}/v1/mills/line-2w`);
    check(stored.status === 200, `GET /v1/mills/line-2w answered ${stored.status}`);
    const storedMill = await stored.json();
    const version = stored.headers.get('etag').replace(/"/g, '');
    // What was stored is the mill the editor showed: the tandem analysis echoes the same mill for it.
    const echo = (await post('/v1/tandem', { tandem: puts[0].body, options: { critical_speed: false, detail: 'summary' } })).body.tandem;
    check(canon(storedMill) === canon(echo), 'the stored mill is the mill the editor showed');
    check(storedMill.stands[1].lubricant.viscosity_Pa_s === 0.0007 && storedMill.exit_thickness_mm.length === 2, 'its second stand\'s own lubricant');
    check(await page.inputValue('#mill-base') === 'line-2w' && (await page.textContent('#mill-base-version')).includes(`version ${version}`), 'the editor now starts from it, its version shown');
    check(/the stored mill line-2w/.test(await page.textContent('#mill-diff-count')), `diff: ${await page.textContent('#mill-diff-count')}`);
    // A change from it: the request names the base and carries the difference only.
    await page.fill('#f-tandem-speed-m-per-s', '12');
    check(/1 field differs from the stored mill line-2w/.test(await page.textContent('#mill-diff-count')), `diff: ${await page.textContent('#mill-diff-count')}`);
    await page.selectOption('#f-options-critical-speed', 'false');
    const sent = [];
    const listenRun = (request) => { if (request.method() === 'POST' && request.url() === `${base}/v1/tandem`) sent.push(request.postDataJSON()); };
    page.on('request', listenRun);
    await runAndWait('participation');
    page.off('request', listenRun);
    check(sent.length === 1 && sent[0].base === 'line-2w' && canon(sent[0].tandem) === canon({ speed_m_per_s: 12 }), `the page sent: ${JSON.stringify(sent)}`);
    const viaBase = (await post('/v1/tandem', sent[0])).body;
    check(viaBase.base && viaBase.base.name === 'line-2w' && String(viaBase.base.version) === version, `base echo: ${JSON.stringify(viaBase.base)}`);
    const full = (await post('/v1/tandem', { tandem: { ...storedMill, speed_m_per_s: 12 }, options: sent[0].options })).body;
    check(JSON.stringify(full.result) === JSON.stringify(viaBase.result), 'the stored mill computes as the mill sent in full');
    const forces = await page.$$eval('#mill-row .mill-stand [data-quantity="force"]', (all) => all.map((n) => Number(n.dataset.value)));
    equalArrays(forces, viaBase.result.steady_state.stands.map((s) => s.force_kN), 'roll forces on the stored mill');
    check(page.url().includes('mill_base=line-2w'), 'the base is in the link');
    // Saved again under its name: the version loaded is replaced (If-Match).
    puts.length = 0;
    await page.click('#mill-save');
    await page.waitForFunction((v) => new RegExp(`saved as line-2w, version (?!${v}\\b)`).test(document.getElementById('mill-save-status').textContent), version, { timeout: 30000 });
    page.off('request', listen);
    check(puts.length === 1 && puts[0].headers['if-match'] === `"${version}"`, `replaced with If-Match: ${JSON.stringify(puts.map((p) => p.headers))}`);
    check((await (await fetch(`${base}/v1/mills/line-2w`)).json()).speed_m_per_s === 12, 'the stored mill now runs at 12 m/s');
    // The mill stored elsewhere, loaded into the editor from the list (asked again when a mill is saved).
    await page.selectOption('#mill-base', 'line-b');
    await page.waitForFunction(() => document.getElementById('f-tandem-spans-tension-MPa-0').value === '70');
    equalArrays((await millInputs('/tandem/exit_thickness_mm/')).map(Number), other.exit_thickness_mm, 'the stored schedule in the editor');
    equalArrays((await millInputs('/tandem/spans/length_m/')).map(Number), other.spans.length_m, 'the stored span in the editor');
    check(/the stored mill line-b/.test(await page.textContent('#mill-diff-count')), `diff: ${await page.textContent('#mill-diff-count')}`);
    await shot('tandem-stored-mill');
    await checkAxe();
    await page.selectOption('#mill-base', '');
    await page.click('#mill-reset');
    await page.selectOption('#f-options-critical-speed', '');
  });

  await test('no console errors', async () => {
    check(consoleErrors.length === 0, consoleErrors.join('\n'));
  });
} finally {
  await browser.close();
  await stopServer(child);
  rmSync(dataDir, { recursive: true, force: true });
}

const failed = results.filter(([, ok]) => !ok).length;
console.log(`${results.length - failed} passed, ${failed} failed; screenshots in ${screenshots}`);
process.exit(failed ? 1 : 0);
