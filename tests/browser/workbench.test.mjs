// The workbench in a real browser: Debian's chromium driven by playwright-core, against a real
// `rollgap serve` on loopback that this script starts and stops. What the page plots is
// compared with a direct call of the API; screenshots of each view go to SCREENSHOT_DIR.
//
//   node workbench.test.mjs <rollgap binary> <screenshot dir>
// Env: ROLLGAP_NODE_TOOLS (npm packages: playwright-core, axe-core), CHROMIUM (/usr/bin/chromium).
import { spawn } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync, statSync } from 'node:fs';
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
function startServer() {
  const child = spawn(binary, ['serve', '--port', '0', '--bind', '127.0.0.1', '--workers', '2'], { stdio: ['ignore', 'ignore', 'pipe'] });
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

// ---- the page --------------------------------------------------------------------------------
const { child, base } = await startServer();
const post = async (route, body) => {
  const response = await fetch(base + route, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  return { status: response.status, body: await response.json() };
};
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
function watch(page) {
  page.on('console', (message) => {
    if (message.type() !== 'error') return;
    if (/status of 422/.test(message.text()) && expected422 > 0) { expected422--; return; }
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
const dataset = (chart, label) => {
  const found = chart.datasets.find((d) => d.label === label);
  check(found, `no dataset '${label}' among ${chart.datasets.map((d) => d.label).join(', ')}`);
  return found.data;
};
async function runAndWait(plot) {
  await page.evaluate(() => document.getElementById('plots').replaceChildren());
  await page.click('#run');
  await page.waitForSelector(`#plot-${plot}`, { timeout: 120000 });
}

try {
  await test('the page is served from the binary under a strict CSP', async () => {
    const response = await page.goto(base + '/');
    check(response.status() === 200, `GET / answered ${response.status()}`);
    const csp = response.headers()['content-security-policy'] || '';
    check(/default-src 'self'/.test(csp) && !/unsafe-inline|unsafe-eval/.test(csp), `CSP: ${csp}`);
    await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
    const html = await (await fetch(base + '/')).text();
    check(!/<script(?![^>]*\bsrc=)[^>]*>/i.test(html) && !/\sstyle=/i.test(html), 'the page has inline script or style');
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

  const patch = { strip: { reduction: 0.2 } };
  await test('an edited field runs the roll gap; the plot is the API data; the neutral point is at the pressure peak', async () => {
    await page.fill('#f-scenario-strip-reduction', '0.2');
    const diff = await page.textContent('#diff');
    check(/\/strip\/reduction: 0\.15 → 0\.2/.test(diff), `diff list: ${diff}`);
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
    const shape = await chartData('mode-shape');
    equalArrays(shape.datasets[0].data, critical.unstable_mode.shape, 'unstable mode shape');
    await shot('stability');
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
    check((await page.$$('#job-list li')).length >= 1, 'the job is listed');
    await shot('sweep');
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

  await test('usable at 1024 x 768 with touch', async () => {
    const tablet = await browser.newContext({ viewport: { width: 1024, height: 768 }, hasTouch: true });
    const touch = watch(await tablet.newPage());
    await touch.goto(link);
    await touch.waitForSelector('#plot-damping', { timeout: 120000 });
    const width = await touch.evaluate(() => document.documentElement.scrollWidth);
    check(width <= 1024, `the page is ${width} px wide at 1024`);
    await shot('touch-1024x768', touch);
    await tablet.close();
  });

  await test('no console errors', async () => {
    check(consoleErrors.length === 0, consoleErrors.join('\n'));
  });
} finally {
  await browser.close();
  await stopServer(child);
}

const failed = results.filter(([, ok]) => !ok).length;
console.log(`${results.length - failed} passed, ${failed} failed; screenshots in ${screenshots}`);
process.exit(failed ? 1 : 0);
