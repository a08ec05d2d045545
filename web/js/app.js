// The workbench: wires the generated forms, the analyses' views, jobs, the URL state and the
// report together. Everything it knows about fields comes from /openapi.json.
import { ProblemError, getJson, call, setToken, token } from './api.js';
import { clearPlots } from './charts.js';
import { OptionsForm, ScenarioForm, clearFieldErrors, resolve, showFieldErrors } from './editor.js';
import { JobRunner, openJob, recentJobs } from './jobs.js';
import { downloadCsv, downloadJson, fillReport, table } from './report.js';
import { readState, writeState } from './state.js';
import { analyses, analysisByKey } from './views.js';

const $ = (id) => document.getElementById(id);
const app = { doc: null, scenario: null, options: null, analysis: null, response: null, report: false };

function optionsSchema(analysis) {
  const request = resolve(app.doc, app.doc.paths[analysis.path].post.requestBody.content['application/json'].schema);
  return request.properties.options;
}

function selectAnalysis(key) {
  app.analysis = analysisByKey(key);
  for (const tab of $('tabs').children) {
    const selected = tab.dataset.key === app.analysis.key;
    tab.setAttribute('aria-selected', String(selected));
    tab.tabIndex = selected ? 0 : -1;
  }
  app.options = new OptionsForm($('options-form'), app.doc, optionsSchema(app.analysis));
  $('run').textContent = app.analysis.job ? `Run ${app.analysis.label.toLowerCase()} as a job` : `Run ${app.analysis.label.toLowerCase()}`;
  $('run-job').hidden = Boolean(app.analysis.job);
}

function buildTabs() {
  for (const analysis of analyses) {
    const tab = document.createElement('button');
    tab.type = 'button';
    tab.setAttribute('role', 'tab');
    tab.id = `tab-${analysis.key}`;
    tab.dataset.key = analysis.key;
    tab.textContent = analysis.label;
    tab.setAttribute('aria-controls', 'options-form');
    tab.addEventListener('click', () => { selectAnalysis(analysis.key); saveState(); });
    $('tabs').append(tab);
  }
  $('tabs').addEventListener('keydown', (event) => {
    const step = { ArrowRight: 1, ArrowLeft: -1 }[event.key];
    if (!step) return;
    const i = analyses.indexOf(app.analysis);
    const next = analyses[(i + step + analyses.length) % analyses.length];
    selectAnalysis(next.key);
    $(`tab-${next.key}`).focus();
  });
}

function saveState() {
  return writeState({ analysis: app.analysis.key, scenario: app.scenario.patch(), options: app.options.options(), view: app.report ? 'report' : null });
}

function showDiff() {
  app.scenario.markChanges();
  const changes = app.scenario.changes();
  $('diff-count').textContent = changes.length ? `${changes.length} field${changes.length > 1 ? 's differ' : ' differs'} from the default` : 'the default scenario';
  $('diff').replaceChildren(...changes.map(([pointer, base, value]) => {
    const item = document.createElement('li');
    item.textContent = `${pointer}: ${base} → ${value}`;
    return item;
  }));
}

function setStatus(text) { $('status').textContent = text; }

function showProblem(problem) {
  const box = $('problem');
  const unplaced = showFieldErrors(document.body, problem.errors);
  box.replaceChildren();
  const title = document.createElement('strong');
  title.textContent = `${problem.title || 'Error'} (${problem.status || ''}${problem.code ? ', ' + problem.code : ''})`;
  const detail = document.createElement('p');
  detail.textContent = problem.detail || '';
  box.append(title, detail);
  const placed = (problem.errors || []).filter((e) => !unplaced.includes(e)).map((e) => e.pointer);
  if (placed.length) {
    const where = document.createElement('p');
    where.textContent = `Shown at the field${placed.length > 1 ? 's' : ''}: ${placed.join(', ')}`;
    box.append(where);
  }
  if (unplaced.length) box.append(table('Other problems', unplaced.map((e) => [e.pointer || '', e.detail, e.bound || ''])));
  box.hidden = false;
}

function render(response) {
  app.response = response;
  const plots = $('plots');
  clearPlots(plots);
  const view = analysisByKey(response.analysis);
  const headline = view.render(response, plots);
  $('headline').replaceChildren(table(`${view.label}: headline figures`, headline, ['quantity', 'value', 'unit']));
  $('result-actions').hidden = false;
  if (app.report) fillReportView();
}

// A run that did not succeed must not leave an earlier result on screen as if it were its own.
function clearResult() {
  app.response = null;
  clearPlots($('plots'));
  $('headline').replaceChildren();
  $('result-actions').hidden = true;
}

const request = () => ({ analysis: app.analysis.key, scenario: app.scenario.patch(), options: app.options.options() });

async function run(asJob) {
  clearFieldErrors(document.body);
  $('problem').hidden = true;
  saveState();
  const body = request();
  $('run').disabled = $('run-job').disabled = true;
  setStatus('running…');
  const started = performance.now();
  try {
    if (asJob || app.analysis.job) {
      $('progress').hidden = $('cancel').hidden = false;
      $('progress').value = 0;
      const job = await runner.run(body);
      if (job.state === 'succeeded') render(job.result.result ? job.result : { ...body, result: job.result });
      else clearResult();
      if (job.state === 'failed') showProblem(job.problem || { detail: 'the job failed' });
      setStatus(`job ${job.state}`);
      listJobs();
    } else {
      const { analysis, ...payload } = body;
      render((await call('POST', app.analysis.path, payload)).body);
      setStatus(`done in ${((performance.now() - started) / 1000).toFixed(2)} s`);
    }
  } catch (error) {
    clearResult();
    if (error instanceof ProblemError) showProblem(error.problem);
    else showProblem({ title: 'Request failed', detail: String(error) });
    setStatus('failed');
  } finally {
    $('run').disabled = $('run-job').disabled = false;
    $('progress').hidden = $('cancel').hidden = true;
  }
}

const runner = new JobRunner({
  onProgress(job) {
    $('progress').value = job.progress || 0;
    setStatus(`job ${job.state}, ${Math.round((job.progress || 0) * 100)} %`);
  },
});

function listJobs() {
  $('job-list').replaceChildren(...recentJobs().map((job) => {
    const item = document.createElement('li');
    const open = document.createElement('button');
    open.type = 'button';
    open.textContent = `${job.analysis} · ${job.created_at || ''}`;
    open.addEventListener('click', async () => {
      try {
        const stored = await openJob(job.id);
        if (stored.state !== 'succeeded') { setStatus(`job ${stored.state}`); return; }
        selectAnalysis(stored.analysis);
        app.scenario.apply(job.request.scenario || {});
        app.options.apply(job.request.options || {});
        showDiff();
        render(stored.result);
        saveState();
      } catch (error) {
        showProblem(error instanceof ProblemError ? error.problem : { detail: String(error) });
      }
    });
    item.append(open);
    return item;
  }));
}

function fillReportView() {
  fillReport($('report-head'), $('report-scenario'), app.response,
    { label: app.analysis.label, version: app.doc.info.version, link: saveState(), changes: app.scenario.changes() });
}

function setReport(on) {
  app.report = on;
  document.body.classList.toggle('report-mode', on);
  $('report-head').hidden = $('report-scenario').hidden = !on;
  $('print').hidden = !on;
  $('report').textContent = on ? 'Back to the workbench' : 'Report view';
  if (on && app.response) fillReportView();
  saveState();
}

async function start() {
  const [doc, base] = await Promise.all([getJson('/openapi.json'), getJson('/v1/scenarios/default')]);
  app.doc = doc;
  $('version').textContent = doc.info.version;
  app.scenario = new ScenarioForm($('scenario-form'), doc, base);
  buildTabs();
  const state = readState();
  selectAnalysis(state.analysis || 'roll_gap');
  app.scenario.apply(state.scenario);
  app.options.apply(state.options);
  showDiff();
  listJobs();

  $('scenario-form').addEventListener('input', showDiff);
  $('scenario-form').addEventListener('change', showDiff);
  $('reset').addEventListener('click', () => { app.scenario.apply({}); showDiff(); clearFieldErrors(document.body); });
  $('run').addEventListener('click', () => run(false));
  $('run-job').addEventListener('click', () => run(true));
  $('cancel').addEventListener('click', () => runner.cancel().catch(() => {}));
  $('download-json').addEventListener('click', () => downloadJson(app.response));
  $('download-csv').addEventListener('click', () => downloadCsv(app.response, analysisByKey(app.response.analysis).csv(app.response)));
  $('copy-link').addEventListener('click', async () => {
    const link = saveState();
    try { await navigator.clipboard.writeText(link); setStatus('link copied'); } catch { setStatus(`link: ${link}`); }
  });
  $('report').addEventListener('click', () => setReport(!app.report));
  $('print').addEventListener('click', () => window.print());
  $('token').value = token();
  $('token').addEventListener('change', (event) => setToken(event.target.value.trim()));

  document.body.dataset.ready = 'true';
  if (state.analysis) {
    if (state.view === 'report') setReport(true);
    await run(false);
  }
}

start().catch((error) => showProblem({ title: 'The workbench could not start', detail: String(error) }));
