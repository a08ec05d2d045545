// The workbench: wires the generated forms, the analyses' views, jobs, the URL state and the
// report together. Everything it knows about fields and analyses comes from /openapi.json (the
// analyses: its x-rollgap-analyses, the rows of the service's analysis table).
import { ProblemError, call, fetchBlob, getJson, setToken, token } from './api.js';
import { clearPlots, labelShown, unitsShown } from './charts.js';
import { MillForm, OptionsForm, ScenarioForm, attachRows, clearFieldErrors, diffPatch, fieldInfo, fieldLabel, mergePatch, patchLeaves, resolve, showFieldErrors, switchInputUnits, valueShown } from './editor.js';
import { JobRunner, openJob, recentJobs, useServerJobList } from './jobs.js';
import { createScenario, saveMill, storedMill, storedMills, storedScenario, storedScenarios, updateScenario } from './scenarios.js';
import { downloadCsv, downloadJson, fillReport, table } from './report.js';
import { readState, writeState } from './state.js';
import { viewOf } from './views.js';

const $ = (id) => document.getElementById(id);
// rows: every analysis of the service; analyses: those the page offers (on_page), in order.
// source: where the result shown came from (the request posted, or the job), for its CSV.
// mill: the tandem mill's editor (the analyses whose subject is "tandem"); millBase: the stored
// mill it starts from ('' the default mill), millVersion its ETag.
const app = { doc: null, defaults: null, baseName: '', millBase: '', millVersion: '', scenario: null, mill: null, options: null, rows: [], analyses: [], analysis: null, response: null, source: null, report: false, partialShown: -1 };

const rowOf = (name) => app.rows.find((row) => row.name === name) || { name, label: name, csv: false };
const analysisNamed = (name) => app.analyses.find((row) => row.name === name) || app.analyses[0];
// An analysis of the tandem mill (x-rollgap-analyses' subject): the mill editor replaces the scenario's.
const ofMill = (row) => Boolean(row) && row.subject === 'tandem';

// The analysis' options component with its defaults (the request body's copy has none, so that
// generated clients may leave members out): the form shows them as placeholders.
function optionsSchema(analysis) {
  if (analysis.options_schema) return { $ref: `#/components/schemas/${analysis.options_schema}` };
  const request = resolve(app.doc, app.doc.paths[analysis.path].post.requestBody.content['application/json'].schema);
  return request.properties.options;
}

function selectAnalysis(name) {
  app.analysis = analysisNamed(name);
  for (const tab of $('tabs').children) {
    const selected = tab.dataset.key === app.analysis.name;
    tab.setAttribute('aria-selected', String(selected));
    tab.tabIndex = selected ? 0 : -1;
  }
  app.options = new OptionsForm($('options-form'), app.doc, optionsSchema(app.analysis));
  $('editor').hidden = ofMill(app.analysis);
  $('mill-editor').hidden = !ofMill(app.analysis);
  const { job } = viewOf(app.analysis.name);
  $('run').textContent = job ? `Run ${app.analysis.label.toLowerCase()} as a job` : `Run ${app.analysis.label.toLowerCase()}`;
  $('run-job').hidden = Boolean(job);
  $('compare-row').hidden = !$('compare-stored').options.length || ofMill(app.analysis);
}

function buildTabs() {
  for (const analysis of app.analyses) {
    const tab = document.createElement('button');
    tab.type = 'button';
    tab.setAttribute('role', 'tab');
    tab.id = `tab-${analysis.name}`;
    tab.dataset.key = analysis.name;
    tab.textContent = analysis.label;
    tab.title = analysis.summary;
    tab.setAttribute('aria-controls', 'options-form');
    tab.addEventListener('click', () => { selectAnalysis(analysis.name); saveState(); });
    $('tabs').append(tab);
  }
  $('tabs').addEventListener('keydown', (event) => {
    const step = { ArrowRight: 1, ArrowLeft: -1 }[event.key];
    if (!step) return;
    const { analyses } = app;
    const i = analyses.indexOf(app.analysis);
    const next = analyses[(i + step + analyses.length) % analyses.length];
    selectAnalysis(next.name);
    $(`tab-${next.name}`).focus();
  });
}

function saveState() {
  return writeState({ analysis: app.analysis.name, base: app.baseName, millBase: app.millBase, scenario: app.scenario.patch(), tandem: app.mill.patch(), options: app.options.options(), view: app.report ? 'report' : null, units: unitsShown() });
}

// SI or plant units (m/min, mPa·s) for what the page shows; the result on screen is drawn again
// in them (the answer is kept: nothing is computed again).
function setUnits(mode, { redraw = true } = {}) {
  switchInputUnits(document, mode);  // the inputs too: a speed typed in m/min, a viscosity in mPa·s
  $('units-si').checked = unitsShown() === 'si';
  $('units-plant').checked = unitsShown() === 'plant';
  if (!redraw) return;
  showDiff();
  showMillDiff();
  if (app.response) render(app.response, app.source);
}

// One changed field: its name and unit, the base's value and the value; its pointer as the tooltip.
function diffItem(name, pointer, base, value) {
  const item = document.createElement('li');
  item.textContent = `${name}: ${base} → ${value}`;
  item.title = pointer;
  item.dataset.pointer = pointer;
  return item;
}

function showDiff() {
  app.scenario.markChanges();
  const changes = app.scenario.changes();
  const base = app.baseName ? `stored scenario ${app.baseName}` : 'default scenario';
  $('diff-count').textContent = changes.length ? `${changes.length} field${changes.length > 1 ? 's differ' : ' differs'} from the ${base}` : `the ${base}`;
  $('diff').setAttribute('aria-label', `Fields that differ from the ${base}`);
  // In the units shown, as the inputs are ("Roll speed [m/min]: 1140 → 1200").
  const item = ([pointer, from, to]) => {
    const { unit } = fieldInfo(app.doc, pointer);
    return diffItem(labelShown(fieldLabel(app.doc, pointer)), pointer, valueShown(from, unit), valueShown(to, unit));
  };
  $('diff').replaceChildren(...changes.map(item));
}

function showMillDiff() {
  app.mill.markChanges();
  const changes = app.mill.changes();
  const base = app.millBase ? `stored mill ${app.millBase}` : 'default mill';
  $('mill-diff-count').textContent = changes.length ? `${changes.length} field${changes.length > 1 ? 's differ' : ' differs'} from the ${base}` : `the ${base}`;
  $('mill-diff').setAttribute('aria-label', `Fields that differ from the ${base}`);
  const item = ([pointer, from, to]) => {
    const { unit } = fieldInfo(app.doc, pointer, 'Tandem');
    return diffItem(labelShown(fieldLabel(app.doc, pointer, 'Tandem')), pointer, valueShown(from ?? '—', unit), valueShown(to, unit));
  };
  $('mill-diff').replaceChildren(...changes.map(item));
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

// What a view needs besides the answer: the document (units of the fields) and the rolling
// speed the editor shows (a running map's operating speed).
// `pinned`: a run kept to compare with ({ response, name }), drawn beside this one where the
// views can (the same sweep, two stabilities); `name`: what the legend calls this run.
function context(response) {
  const compare = { pinned: app.pinned, name: response ? runName(response) : 'this run' };
  if (ofMill(app.analysis)) return { doc: app.doc, speed: app.mill.full().speed_m_per_s, ...compare };
  const full = mergePatch(structuredClone(app.scenario.base), app.scenario.patch());
  return { doc: app.doc, speed: full.rolls && full.rolls.speed_m_per_s, ...compare };
}

// A run named for a legend: its stand and its first differences from it, by title
// ("default stand: Reduction 0.25, Flow stress 610").
function runName(response) {
  const from = response.base ? response.base.name : 'default stand';
  if (!response.scenario) return from;
  const stand = response.base && response.base.name === app.baseName ? app.scenario.base : app.defaults;
  const leaves = patchLeaves(diffPatch(stand, response.scenario, { nulls: false }) || {});
  const what = leaves.slice(0, 2).map(([pointer, value]) => `${fieldInfo(app.doc, pointer).title} ${Array.isArray(value) ? value.join(', ') : value}`);
  if (leaves.length > 2) what.push(`${leaves.length - 2} more`);
  return what.length ? `${from}: ${what.join(', ')}` : from;
}

// Pins the result shown (or unpins): the next runs draw it beside theirs. `name`: the legend's
// (by default the run's stand and its first differences).
function setPinned(response, name = response && runName(response)) {
  app.pinned = response ? { response, name } : null;
  $('pinned').hidden = !app.pinned;
  $('pinned-name').textContent = app.pinned ? app.pinned.name : '';
  $('pin').textContent = app.pinned ? 'Pin this run instead' : 'Pin this run to compare';
  if (app.response) render(app.response, app.source);
}

// `source`: { path, body } posted, or { job } (its id): where the same result's CSV is asked.
function render(response, source) {
  app.response = response;
  app.source = source;
  const plots = $('plots');
  clearPlots(plots);
  const row = rowOf(response.analysis);
  const headline = viewOf(response.analysis).render(response, plots, context(response));
  $('headline').replaceChildren(table(`${row.label}: headline figures`, headline, ['quantity', 'value', 'unit']));
  $('download-csv').hidden = !row.csv;
  $('result-actions').hidden = false;
  if (app.report) fillReportView();
}

// One request's answer, as a job when its view runs as one (a sweep), else posted.
async function answerOf(body) {
  if (!viewOf(body.analysis).job) {
    const { analysis, ...payload } = body;
    return (await call('POST', analysisNamed(analysis).path, payload)).body;
  }
  const job = await runner.run(body);
  if (job.state !== 'succeeded') throw new ProblemError(0, job.problem || { title: `The stored stand's run ${job.state}`, detail: `the job ${job.state}` });
  return job.result.result ? job.result : { ...body, result: job.result };
}

// The editor's stand against a stored one: the analysis and options shown, run on the stored
// stand as it is stored (its name as base, no changes), pinned under its name and version; then
// the editor's run, drawn beside it as any pinned run is.
async function compareWithStored() {
  const name = $('compare-stored').value;
  if (!name || ofMill(app.analysis)) return;
  clearFieldErrors(document.body);
  $('problem').hidden = true;
  $('compare-run').disabled = true;
  setStatus(`running the stored stand ${name}…`);
  try {
    const response = await answerOf({ analysis: app.analysis.name, base: name, scenario: {}, options: app.options.options() });
    const version = response.base && response.base.version ? ` (version ${String(response.base.version).replace(/"/g, '')})` : '';
    setPinned(response, `stored stand ${name}${version}`);
  } catch (error) {
    showProblem(error instanceof ProblemError ? error.problem : { title: `The stored stand ${name} could not be run`, detail: String(error) });
    setStatus('failed');
    return;
  } finally {
    $('compare-run').disabled = false;
  }
  await run(false);
}

// A run that did not succeed must not leave an earlier result on screen as if it were its own.
function clearResult() {
  app.response = app.source = null;
  clearPlots($('plots'));
  $('headline').replaceChildren();
  $('result-actions').hidden = true;
}

const request = () => (ofMill(app.analysis)
  ? { analysis: app.analysis.name, ...(app.millBase ? { base: app.millBase } : {}), tandem: app.mill.patch(), options: app.options.options() }
  : { analysis: app.analysis.name, ...(app.baseName ? { base: app.baseName } : {}), scenario: app.scenario.patch(), options: app.options.options() });

// A running sweep or map: its finished points (the job's partial_result) drawn as they arrive.
function renderPartial(job, body) {
  const view = viewOf(body.analysis);
  const partial = job.partial_result;
  if (job.state !== 'running' || !view.partial || !partial || !Array.isArray(partial.points)) return;
  if (partial.points.length === app.partialShown) return;
  app.partialShown = partial.points.length;
  clearPlots($('plots'));
  const headline = view.render({ analysis: body.analysis, options: body.options, result: view.partial(body, partial), partial: true }, $('plots'), context());
  $('headline').replaceChildren(table(`${rowOf(body.analysis).label} (running): the finished points`, headline, ['quantity', 'value', 'unit']));
}

async function run(asJob) {
  clearFieldErrors(document.body);
  $('problem').hidden = true;
  clearResult();  // the earlier answer is not this run's
  saveState();
  const body = request();
  $('run').disabled = $('run-job').disabled = true;
  setStatus('running…');
  const started = performance.now();
  try {
    if (asJob || viewOf(app.analysis.name).job) {
      $('progress').hidden = $('cancel').hidden = false;
      $('progress').value = 0;
      app.partialShown = -1;
      const job = await runner.run(body);
      if (job.state === 'succeeded') render(job.result.result ? job.result : { ...body, result: job.result }, { job: job.id });
      else clearResult();
      if (job.state === 'failed') showProblem(job.problem || { detail: 'the job failed' });
      setStatus(`job ${job.state}`);
      listJobs();
    } else {
      const { analysis, ...payload } = body;
      render((await call('POST', app.analysis.path, payload)).body, { path: app.analysis.path, body: payload });
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
  onProgress(job, body) {
    $('progress').value = job.progress || 0;
    const points = Number.isInteger(job.points_total) ? `, ${job.points_done || 0} of ${job.points_total} points` : '';
    setStatus(`job ${job.state}, ${Math.round((job.progress || 0) * 100)} %${points}`);
    renderPartial(job, body);
  },
});

async function listJobs(cursor) {
  let page;
  try { page = await recentJobs(cursor); } catch { return; }  // the list is a convenience: the page works without it
  const items = page.jobs.map((job) => {
    const item = document.createElement('li');
    const open = document.createElement('button');
    open.type = 'button';
    open.textContent = `${job.analysis} · ${job.state ? job.state + ' · ' : ''}${job.created_at || ''}`;
    open.addEventListener('click', async () => {
      try {
        const stored = await openJob(job.id);
        if (stored.state !== 'succeeded') { setStatus(`job ${stored.state}`); return; }
        if (rowOf(stored.analysis).subject === 'items') {  // a batch: its rows, the editor untouched
          render(stored.result, { job: job.id });
          return;
        }
        selectAnalysis(stored.analysis);
        if (stored.result.tandem) app.mill.applyFull(stored.result.tandem);
        else app.scenario.applyFull(stored.result.scenario || {});
        app.options.apply(stored.result.options || {});
        showDiff();
        showMillDiff();
        render(stored.result, { job: job.id });
        saveState();
      } catch (error) {
        showProblem(error instanceof ProblemError ? error.problem : { detail: String(error) });
      }
    });
    item.append(open);
    return item;
  });
  if (page.next) {
    const more = document.createElement('button');
    more.type = 'button';
    more.textContent = 'Older jobs';
    more.addEventListener('click', () => listJobs(page.next));
    const item = document.createElement('li');
    item.append(more);
    items.push(item);
  }
  $('jobs-title').textContent = page.source === 'service' ? 'Recent jobs (this service)' : 'Recent jobs (this browser)';
  if (cursor) {  // older ones: after those shown, in place of their "Older jobs" button
    $('job-list').lastElementChild.remove();
    $('job-list').append(...items);
  } else {
    $('job-list').replaceChildren(...items);
  }
}

// Start from a stored scenario (or the default, name ''): the editor shows it, the diff and
// the requests' patch are relative to it, the requests name it as `base`.
async function chooseBase(name, patch = {}) {
  if (name) {
    const { scenario, version } = await storedScenario(name);
    app.scenario.setBase(scenario);
    app.baseVersion = version;
    $('base-version').textContent = version ? `version ${version.replace(/"/g, '')}` : '';
  } else {
    app.scenario.setBase(app.defaults);
    app.baseVersion = '';
    $('base-version').textContent = '';
  }
  // A stored stand can be calibrated from a coil's measurements; the default cannot.
  $('calibrate-stored').hidden = !name;
  $('calibrate-stored-status').textContent = '';
  app.baseName = name;
  $('base').value = name;
  $('save-name').value = name;
  $('save-status').textContent = '';
  app.scenario.apply(patch);
  showDiff();
}

// POST /v1/scenarios/{name}/calibrate on the stored stand the editor starts from, with the
// version it shows as If-Match: the fit is shown as a calibration, the stand reloaded at its
// new version (the editor keeps its own changes on top).
async function calibrateStored() {
  const status = $('calibrate-stored-status');
  const read = (id) => { try { return JSON.parse($(id).value || '[]'); } catch { return $(id).value; } };
  const name = app.baseName;
  status.textContent = 'calibrating…';
  $('problem').hidden = true;
  try {
    const options = { parameters: read('calibrate-stored-parameters'), observations: read('calibrate-stored-observations') };
    const { body } = await call('POST', `/v1/scenarios/${encodeURIComponent(name)}/calibrate`, { options }, { 'If-Match': app.baseVersion });
    const patch = app.scenario.patch();
    render(body, { stored: body.stored });
    if (body.stored) {
      await chooseBase(name, patch);
      status.textContent = `stored as version ${body.stored.version} (${body.result.status})`;
    } else {
      status.textContent = `not stored: the fit ended ${body.result.status}`;
    }
  } catch (error) {
    status.textContent = error instanceof ProblemError ? `refused (${error.status})` : 'failed';
    showProblem(error instanceof ProblemError ? error.problem : { detail: String(error) });
  }
}

// The stored stands in the "Start from" list (asked again after a save); null when the service has none.
async function listStoredScenarios() {
  const list = await storedScenarios(app.doc).catch(() => null);
  if (!list) return null;
  $('base').replaceChildren(Object.assign(document.createElement('option'), { value: '', textContent: 'the default scenario' }),
    ...list.map((s) => Object.assign(document.createElement('option'), { value: s.name, textContent: `${s.name}${s.updated_at ? ` (${s.updated_at})` : ''}` })));
  $('base').value = app.baseName;
  const compared = $('compare-stored').value;
  $('compare-stored').replaceChildren(...list.map((s) => Object.assign(document.createElement('option'), { value: s.name, textContent: s.name })));
  if (list.some((s) => s.name === compared)) $('compare-stored').value = compared;
  return list;
}

async function offerStoredScenarios(wanted) {
  const list = await listStoredScenarios();
  if (!list) return;
  $('base-row').hidden = $('save-row').hidden = false;
  if (!app.storedOffered) {  // once: a changed fragment offers them again
    app.storedOffered = true;
    $('base').addEventListener('change', () => chooseBase($('base').value).then(saveState).catch((error) => showProblem(error.problem || { detail: String(error) })));
    $('save').addEventListener('click', saveCurrentStand);
    $('compare-run').addEventListener('click', compareWithStored);
  }
  $('compare-row').hidden = !list.length || ofMill(app.analysis);
  if (wanted && list.some((s) => s.name === wanted)) await chooseBase(wanted);
}

// The stand the editor shows, stored under the name given: the stored stand it starts from gets
// the editor's changes as its next version (PATCH, If-Match the version loaded: its calibration
// posterior is kept unless a field it describes changes); any other name is created
// (PUT, If-None-Match: *, the complete scenario). A 412 says what happened and what to do.
async function saveCurrentStand() {
  const name = $('save-name').value.trim();
  const status = $('save-status');
  $('problem').hidden = true;
  if (!name) { status.textContent = 'give the stand a name'; return; }
  const update = name === app.baseName;
  const patch = app.scenario.patch();
  if (update && !Object.keys(patch).length) { status.textContent = `nothing to save: no field differs from ${name}, version ${app.baseVersion.replace(/"/g, '')}`; return; }
  try {
    const version = update
      ? await updateScenario(name, patch, app.baseVersion)
      : await createScenario(name, mergePatch(structuredClone(app.scenario.base), patch));
    await chooseBase(name);
    await listStoredScenarios();
    saveState();
    status.textContent = `saved as ${name}, version ${version.replace(/"/g, '')}`;
  } catch (error) {
    status.textContent = 'not saved';
    if (!(error instanceof ProblemError)) { showProblem({ title: 'Saving the stand failed', detail: String(error) }); return; }
    if (error.status !== 412) { showProblem(error.problem); return; }
    const loaded = app.baseVersion.replace(/"/g, '');
    showProblem(update
      ? { ...error.problem, title: `Not saved: ${name} was changed meanwhile`,
        detail: `Someone stored a newer version of ${name} after you loaded version ${loaded}, so saving would overwrite their change. Your changes are still in the editor: load the latest version with them on top (below), check it, and save again — or save under another name.` }
      : { ...error.problem, title: `Not saved: a stand named ${name} exists`,
        detail: `A stand named ${name} is stored already and a new name never replaces one. To update it, choose it under "Start from" and save; otherwise give another name.` });
    if (update) {
      const rebase = document.createElement('button');
      rebase.type = 'button';
      rebase.id = 'save-rebase';
      rebase.textContent = `Load the latest ${name} with my changes on top`;
      rebase.addEventListener('click', async () => {
        try {
          await chooseBase(name, patch);
          $('problem').hidden = true;
          status.textContent = `your changes are on ${name}, version ${app.baseVersion.replace(/"/g, '')}: check them and save`;
          saveState();
        } catch (again) { showProblem(again.problem || { detail: String(again) }); }
      });
      $('problem').append(rebase);
    }
  }
}

// Start the mill editor from a stored mill (or the default, name ''): the editor shows it, the
// diff and the requests' patch are relative to it, the requests name it as `base`.
async function chooseMillBase(name, patch = {}) {
  if (name) {
    const { mill, version } = await storedMill(name);
    app.mill.setBase(mill);
    app.millVersion = version;
  } else {
    app.mill.setBase(null);
    app.millVersion = '';
  }
  app.millBase = name;
  $('mill-base').value = name;
  $('mill-base-version').textContent = app.millVersion ? `version ${app.millVersion.replace(/"/g, '')}` : '';
  $('mill-save-name').value = name;
  $('mill-save-status').textContent = '';
  app.mill.apply(patch);
  showMillDiff();
}

async function listStoredMills() {
  const list = await storedMills(app.doc).catch(() => null);
  if (!list) return false;
  $('mill-base').replaceChildren(Object.assign(document.createElement('option'), { value: '', textContent: 'the default mill' }),
    ...list.map((m) => Object.assign(document.createElement('option'), { value: m.name, textContent: `${m.name}${m.updated_at ? ` (${m.updated_at})` : ''}` })));
  $('mill-base').value = app.millBase;
  return true;
}

async function offerStoredMills(wanted, patch) {
  if (!(await listStoredMills())) return;
  $('mill-base-row').hidden = $('mill-save-row').hidden = false;
  if (!app.millsOffered) {  // once: a changed fragment offers them again
    app.millsOffered = true;
    $('mill-base').addEventListener('change', () => chooseMillBase($('mill-base').value).then(saveState).catch((error) => showProblem(error.problem || { detail: String(error) })));
    $('mill-save').addEventListener('click', saveCurrentMill);
  }
  if (wanted && [...$('mill-base').options].some((o) => o.value === wanted)) await chooseMillBase(wanted, patch);
}

// The mill the editor shows, stored under the name given: replacing the stored mill it was
// loaded from (If-Match its version), or a new name only (If-None-Match: *).
async function saveCurrentMill() {
  const name = $('mill-save-name').value.trim();
  $('problem').hidden = true;
  if (!name) { $('mill-save-status').textContent = 'give the mill a name'; return; }
  try {
    const version = await saveMill(name, app.mill.full(), name === app.millBase ? app.millVersion : '');
    await listStoredMills();
    await chooseMillBase(name);
    saveState();
    $('mill-save-status').textContent = `saved as ${name}, version ${version.replace(/"/g, '')}`;
  } catch (error) {
    $('mill-save-status').textContent = 'not saved';
    showProblem(error instanceof ProblemError ? error.problem : { title: 'Saving the mill failed', detail: String(error) });
  }
}

function fillReportView() {
  const mill = ofMill(rowOf(app.response.analysis));
  fillReport($('report-head'), $('report-scenario'), app.response,
    { label: app.analysis.label, version: app.doc.info.version, link: saveState(), changes: mill ? app.mill.changes() : app.scenario.changes(),
      name: (pointer) => fieldLabel(app.doc, pointer, mill ? 'Tandem' : 'Scenario'),
      base: mill ? (app.millBase ? `stored mill ${app.millBase}` : 'default mill') : app.baseName ? `stored scenario ${app.baseName}` : 'default scenario' });
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

// The CSV of the result shown, as the service writes it: the same request posted again with
// Accept: text/csv, or the job's result asked in CSV (no second computation).
async function downloadResultCsv() {
  const { response, source } = app;
  if (!response || !source) return;
  // In plant units the service writes the table in them (speeds in m/min, viscosities in mPa·s).
  const query = unitsShown() === 'plant' ? '?units=plant' : '';
  try {
    const csv = source.job
      ? await fetchBlob('GET', `/v1/jobs/${encodeURIComponent(source.job)}${query}`, undefined, 'text/csv')
      : await fetchBlob('POST', `${source.path}${query}`, source.body, 'text/csv');
    downloadCsv(response.analysis, csv);
  } catch (error) {
    showProblem(error instanceof ProblemError ? error.problem : { title: 'Download failed', detail: String(error) });
  }
}

async function start() {
  const [doc, base] = await Promise.all([getJson('/openapi.json'), getJson('/v1/scenarios/default')]);
  app.doc = doc;
  app.rows = Array.isArray(doc['x-rollgap-analyses']) ? doc['x-rollgap-analyses'] : [];
  app.analyses = app.rows.filter((row) => row.on_page && doc.paths[row.path]);
  if (!app.analyses.length) throw new Error('the service\'s OpenAPI document lists no analysis for the page (x-rollgap-analyses)');
  app.defaults = base;
  useServerJobList(doc);
  $('version').textContent = doc.info.version;
  app.scenario = new ScenarioForm($('scenario-form'), doc, base);
  app.mill = new MillForm($('mill-form'), doc, base);
  buildTabs();
  const state = readState();
  await restore(state);
  listJobs();

  $('scenario-form').addEventListener('input', showDiff);
  $('scenario-form').addEventListener('change', showDiff);
  $('calibrate-stored-run').addEventListener('click', calibrateStored);
  // The stored stand's calibration: its fields and measurements as rows, as the analysis' are.
  const calibrateOptions = resolve(doc, doc.components.schemas.CalibrateOptions || {});
  for (const member of ['parameters', 'observations']) {
    if (calibrateOptions.properties && calibrateOptions.properties[member]) attachRows($(`calibrate-stored-${member}`), doc, calibrateOptions.properties[member]);
  }
  $('reset').addEventListener('click', () => { app.scenario.apply({}); showDiff(); clearFieldErrors(document.body); });
  // The mill's rows are rebuilt when the number of stands changes: the diff follows every input.
  $('mill-form').addEventListener('input', showMillDiff);
  $('mill-form').addEventListener('change', showMillDiff);
  $('mill-reset').addEventListener('click', () => { app.mill.apply({}); showMillDiff(); clearFieldErrors(document.body); });  // to its base
  // The calibration's answer: a merge patch onto the defaults, shown as the editor's scenario.
  $('plots').addEventListener('use-scenario', (event) => {
    app.scenario.applyFull(mergePatch(structuredClone(app.defaults), event.detail || {}));
    showDiff();
    saveState();
    setStatus('the calibrated scenario is in the editor');
  });
  $('run').addEventListener('click', () => run(false));
  $('run-job').addEventListener('click', () => run(true));
  $('cancel').addEventListener('click', () => runner.cancel().catch(() => {}));
  $('download-json').addEventListener('click', () => downloadJson(app.response));
  $('download-csv').addEventListener('click', downloadResultCsv);
  $('pin').addEventListener('click', () => setPinned(app.response));
  $('unpin').addEventListener('click', () => setPinned(null));
  $('copy-link').addEventListener('click', async () => {
    const link = saveState();
    try { await navigator.clipboard.writeText(link); setStatus('link copied'); } catch { setStatus(`link: ${link}`); }
  });
  $('report').addEventListener('click', () => setReport(!app.report));
  $('print').addEventListener('click', () => window.print());
  for (const id of ['units-si', 'units-plant']) $(id).addEventListener('change', (event) => { setUnits(event.target.value); saveState(); });
  $('token').value = token();
  $('token').addEventListener('change', (event) => setToken(event.target.value.trim()));

  document.body.dataset.ready = 'true';
  await runLinked(state);
  // A link pasted over this page's (or the back button): the view it names, as on opening it.
  window.addEventListener('hashchange', async () => {
    const linked = readState();
    await restore(linked);
    await runLinked(linked);
  });
}

// The view a link names: its analysis, stored scenario, fields, mill and options.
async function restore(state) {
  setUnits(state.units, { redraw: false });  // the result is cleared below
  selectAnalysis(state.analysis);
  await offerStoredScenarios(state.base);
  app.scenario.apply(state.scenario);
  app.mill.apply(state.tandem);
  await offerStoredMills(state.millBase, state.tandem);
  app.options.apply(state.options);
  showDiff();
  showMillDiff();
  clearFieldErrors(document.body);
  clearResult();
  if (state.view === 'report' || app.report) setReport(state.view === 'report');
}

// The members of the analysis' options that a request must give (a sweep's parameter, a map's
// axes, a fit's observations).
function missingOptions(options) {
  const schema = resolve(app.doc, optionsSchema(app.analysis) || {});
  return (schema.required || []).filter((name) => options[name] === undefined);
}

// Opening a link shows its result when that is cheap and complete: a synchronous analysis whose
// options are all there runs at once; a job's analysis (a sweep, a map, a fit) waits for Run,
// and a link without its required options says what is missing instead of showing a 422.
async function runLinked(state) {
  if (!state.analysis) return;
  const missing = missingOptions(state.options);
  if (missing.length) {
    setStatus(`choose ${missing.join(', ')} for the ${app.analysis.label.toLowerCase()}, then Run`);
    return;
  }
  if (viewOf(app.analysis.name).job) {
    setStatus(`the link's ${app.analysis.label.toLowerCase()} runs as a job: press Run to start it`);
    return;
  }
  await run(false);
}

start().catch((error) => showProblem({ title: 'The workbench could not start', detail: String(error) }));
