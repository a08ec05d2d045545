// Contract test: real responses of every route and analysis of a running `rollgap serve`,
// validated against the OpenAPI document the same service serves (ajv, JSON Schema 2020-12 as
// OpenAPI 3.1 uses it). Every status a response carries must be declared for its operation,
// with its content type, and the body must match the declared schema.
//
// usage: node validate_responses.mjs path/to/rollgap
// The cases are a table: a route or analysis added later joins by adding a row. A row's `expect`
// checks what the row is about (the status of the outcome it provokes), so a scenario that no
// longer reaches, say, `skidding` fails loudly instead of validating something else.
import { createRequire } from 'node:module';
import { mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { startService, toolsDir } from './service.mjs';

const require = createRequire(`${toolsDir()}/`);
const Ajv2020 = require('ajv/dist/2020').default;
const addFormats = require('ajv-formats');

const binary = process.argv[2];
if (!binary) throw new Error('usage: node validate_responses.mjs path/to/rollgap');

const json = (body) => ({ body: JSON.stringify(body), headers: { 'Content-Type': 'application/json' } });
const skids = { lubricant: { limiting_shear: false }, rolls: { speed_m_per_s: 40 } };
// A two-stand mill: its three critical speeds take a tenth of a second (docs/model.md §12.7).
const twoStands = { entry_thickness_mm: 2.25, exit_thickness_mm: [1.88, 1.6], spans: { length_m: [5], tension_MPa: [60] }, stands: [{}, {}] };
const at = (pointer) => (document) => pointer.split('/').slice(1).reduce((node, key) => node?.[key], document);
const equals = (pointer, value) => (document) => {
  const actual = at(pointer)(document);
  if (actual !== value) throw new Error(`${pointer} is ${JSON.stringify(actual)}, expected ${JSON.stringify(value)}`);
};
const every = (...checks) => (document) => checks.forEach((check) => check(document));
// A computed figure within a relative tolerance of an independent one.
const near = (pointer, value, relative) => (document) => {
  const actual = at(pointer)(document);
  if (!(Math.abs(actual - value) <= relative * Math.abs(value))) throw new Error(`${pointer} is ${JSON.stringify(actual)}, expected ${value} ± ${relative * 100} %`);
};

// [name, method, path, request, expected HTTP status, check of the body]
const cases = [
  ['default scenario', 'GET', '/v1/scenarios/default', {}, 200],
  ['openapi', 'GET', '/openapi.json', {}, 200],
  ['livez', 'GET', '/livez', {}, 200],
  ['readyz', 'GET', '/readyz', {}, 200],
  ['metrics', 'GET', '/metrics', {}, 200],
  ['roll gap', 'POST', '/v1/roll-gap', json({}), 200, equals('/result/status', 'ok')],
  ['roll gap without distributions', 'POST', '/v1/roll-gap', json({ options: { distributions: false } }), 200,
    (d) => { if ('distribution' in d.result) throw new Error('distribution present'); }],
  ['roll gap skidding', 'POST', '/v1/roll-gap', json({ scenario: skids }), 200, equals('/result/status', 'skidding')],
  ['roll gap csv', 'POST', '/v1/roll-gap', { ...json({}), accept: 'text/csv' }, 200],
  ['stability', 'POST', '/v1/stability', json({}), 200, equals('/result/critical_speed/status', 'found')],
  ['stability stable in range', 'POST', '/v1/stability',
    json({ options: { speed_min_m_per_s: 5, speed_max_m_per_s: 15 } }), 200,
    equals('/result/critical_speed/status', 'stable_in_range')],
  ['stability unstable at lower bound', 'POST', '/v1/stability',
    json({ options: { speed_min_m_per_s: 20.5, speed_max_m_per_s: 25 } }), 200,
    equals('/result/critical_speed/status', 'unstable_at_lower_bound')],
  ['stability no steady state', 'POST', '/v1/stability',
    json({ scenario: skids, options: { speed_min_m_per_s: 39, speed_max_m_per_s: 41 } }), 200,
    every(equals('/result/status', 'no_steady_state'), equals('/result/critical_speed/status', 'no_steady_state'))],
  ['stability summary', 'POST', '/v1/stability', json({ options: { detail: 'summary' } }), 200,
    (d) => { if ('scan' in d.result.critical_speed) throw new Error('scan in a summary'); }],
  ['stability without search', 'POST', '/v1/stability', json({ options: { critical_speed: false } }), 200,
    equals('/result/critical_speed', null)],
  ['stability csv scan', 'POST', '/v1/stability', { ...json({}), accept: 'text/csv' }, 200],
  ['stability csv branches', 'POST', '/v1/stability?table=damping_branches', { ...json({}), accept: 'text/csv' }, 200],
  ['stability csv summary has no scan', 'POST', '/v1/stability', { ...json({ options: { detail: 'summary' } }), accept: 'text/csv' }, 406],
  ['stability csv unknown table', 'POST', '/v1/stability?table=nothing', { ...json({}), accept: 'text/csv' }, 406],
  ['amplitude', 'POST', '/v1/amplitude', json({}), 200, equals('/result/points/0/status', 'settled')],
  ['amplitude limit reached', 'POST', '/v1/amplitude',
    json({ options: { speeds_m_per_s: [21], excitation_amplitude_MPa: 20 } }), 200,
    equals('/result/points/0/status', 'limit_reached')],
  ['amplitude time series', 'POST', '/v1/amplitude',
    json({ options: { speeds_m_per_s: [10, 15], window_s: 0.5, time_series: true, time_series_points: 50 } }), 200,
    (d) => { if (d.result.points[1].time_series.time_s.length === 0) throw new Error('no time series'); }],
  ['amplitude no steady state', 'POST', '/v1/amplitude', json({ scenario: skids }), 200,
    equals('/result/points/0/status', 'no_steady_state')],
  ['amplitude csv time series', 'POST', '/v1/amplitude?table=time_series',
    { ...json({ options: { window_s: 0.2, time_series: true, time_series_points: 20 } }), accept: 'text/csv' }, 200],
  ['tension cycle', 'POST', '/v1/tension-cycle', json({}), 200, equals('/result/status', 'ok')],
  ['tension cycle no steady state', 'POST', '/v1/tension-cycle', json({ scenario: skids }), 200,
    equals('/result/status', 'no_steady_state')],
  ['tension cycle csv', 'POST', '/v1/tension-cycle', { ...json({ options: { phases: [0.25, 0.75] } }), accept: 'text/csv' }, 200],
  ['sweep critical speed', 'POST', '/v1/sweeps',
    json({ options: { parameter: '/lubricant/viscosity_Pa_s', values: [0.0004, 0.0007] } }), 200,
    equals('/result/points/0/status', 'found')],
  ['sweep amplitude over a range', 'POST', '/v1/sweeps',
    json({ options: { parameter: '/rolls/speed_m_per_s', range: { from: 10, to: 12, count: 2 }, quantity: 'amplitude',
      amplitude: { window_s: 0.5 } } }), 200,
    equals('/result/value_name', 'value_m_per_s')],
  ['sweep dimensionless', 'POST', '/v1/sweeps',
    json({ options: { parameter: '/strip/reduction', values: [0.1, 0.2], critical_speed: { speed_step_m_per_s: 0.5 } } }), 200,
    equals('/result/value_name', 'value')],
  ['sweep csv', 'POST', '/v1/sweeps',
    { ...json({ options: { parameter: '/lubricant/viscosity_Pa_s', values: [0.0004, 0.0007] } }), accept: 'text/csv' }, 200],
  ['map', 'POST', '/v1/maps',
    json({ options: { parameters: [{ parameter: '/strip/reduction', values: [0.15, 0.25] },
      { parameter: '/lubricant/viscosity_Pa_s', values: [0.0005, 0.0008] }],
    critical_speed: { speed_step_m_per_s: 0.5 } } }), 200,
    every(equals('/result/cells/0/status', 'found'), equals('/result/parameters/1/unit', 'Pa.s'))],
  ['map csv', 'POST', '/v1/maps',
    { ...json({ options: { parameters: [{ parameter: '/strip/reduction', values: [0.15] },
      { parameter: '/lubricant/viscosity_Pa_s', values: [0.0005, 0.0008] }] } }), accept: 'text/csv' }, 200],
  ['evaluate', 'POST', '/v1/evaluate', json({}), 200, equals('/result/critical_speed/status', 'found')],
  ['evaluate summary', 'POST', '/v1/evaluate', json({ options: { detail: 'summary' } }), 200,
    (d) => { if ('distribution' in d.result.roll_gap || 'windows' in d.result.amplitude) throw new Error('not a summary'); }],
  ['evaluate no steady state', 'POST', '/v1/evaluate', json({ scenario: skids }), 200,
    every(equals('/result/roll_gap/status', 'skidding'), equals('/result/amplitude/status', 'no_steady_state'))],
  ['evaluate csv', 'POST', '/v1/evaluate', { ...json({}), accept: 'text/csv' }, 406],
  ['calibrate', 'POST', '/v1/calibrate',
    json({ options: { parameters: [{ field: '/strip/flow_stress_MPa' }], observations: [
      { quantity: 'roll_force_kN', value: 9000, standard_uncertainty: 60 },
      { scenario: { strip: { reduction: 0.3 } }, quantity: 'roll_force_kN', value: 11000, standard_uncertainty: 80 }] } }),
    200, equals('/result/parameters/0/field', '/strip/flow_stress_MPa')],
  ['calibrate csv', 'POST', '/v1/calibrate?table=observations',
    { ...json({ options: { parameters: [{ field: '/strip/flow_stress_MPa' }], observations: [
      { quantity: 'roll_force_kN', value: 9000, standard_uncertainty: 60 }] } }), accept: 'text/csv' }, 200],
  ['tandem', 'POST', '/v1/tandem', json({ options: { critical_speed: false } }), 200,
    every(equals('/result/steady_state/status', 'ok'), equals('/tandem/stands/4/rolls/radius_mm', 280))],
  ['tandem two stands with critical speeds', 'POST', '/v1/tandem', json({ tandem: twoStands }), 200,
    every(equals('/result/critical_speeds/frozen/status', 'found'),
      equals('/result/steady_state/stands/1/stand', 2))],
  ['tandem csv stands', 'POST', '/v1/tandem', { ...json({ options: { critical_speed: false } }), accept: 'text/csv' }, 200],
  ['tandem csv crossings', 'POST', '/v1/tandem?table=crossings', { ...json({ tandem: twoStands }), accept: 'text/csv' }, 200],
  ['tandem skidding stand', 'POST', '/v1/tandem',
    json({ tandem: { ...twoStands, stands: [{}, { friction: { model: 'coulomb', coulomb_coefficient: 0.001 } }] },
      options: { critical_speed: false } }), 200,
    every(equals('/result/steady_state/status', 'no_steady_state'), equals('/result/stability/status', 'no_steady_state'))],
  ['tandem invalid', 'POST', '/v1/tandem',
    json({ tandem: { stands: [{}, {}, {}, { rolls: { radius_mm: 5 } }, {}] } }), 422,
    equals('/errors/0/pointer', '/tandem/stands/3/rolls/radius_mm')],
  ['tandem seven stands', 'POST', '/v1/tandem', json({ tandem: { stands: [{}, {}, {}, {}, {}, {}, {}] } }), 422,
    equals('/errors/0/pointer', '/tandem/stands')],
  ['tandem time series csv', 'POST', '/v1/tandem?table=time_series',
    { ...json({ tandem: twoStands, options: { critical_speed: false, time_series: true, time_series_points: 20 } }), accept: 'text/csv' }, 200],
  ['tandem time series', 'POST', '/v1/tandem',
    json({ tandem: twoStands, options: { critical_speed: false, time_series: true, time_series_points: 20 } }), 200,
    equals('/result/time_series/status', 'ok')],
  ['tandem job', 'POST', '/v1/jobs', json({ analysis: 'tandem', tandem: twoStands }), 202],
  ['mill sweep of stability', 'POST', '/v1/tandem/sweeps',
    json({ tandem: twoStands, options: { parameter: '/spans/length_m/0', values: [4, 6], quantity: 'stability' } }), 200,
    every(equals('/result/value_name', 'value_m'), equals('/result/points/1/value_m', 6))],
  ['mill sweep of critical speeds', 'POST', '/v1/tandem/sweeps',
    json({ tandem: twoStands, options: { parameter: '/spans/tension_MPa', values: [60],
      critical_speed: { speed_min_m_per_s: 5, speed_max_m_per_s: 20 } } }), 200,
    equals('/result/points/0/kind', 'nominal_delay')],
  ['mill sweep csv', 'POST', '/v1/tandem/sweeps',
    { ...json({ tandem: twoStands, options: { parameter: '/speed_m_per_s', values: [10, 12], quantity: 'stability' } }), accept: 'text/csv' }, 200],
  ['mill sweep bad value', 'POST', '/v1/tandem/sweeps',
    json({ tandem: twoStands, options: { parameter: '/spans/length_m/0', values: [-1], quantity: 'stability' } }), 422,
    equals('/errors/0/pointer', '/options/values/0')],
  ['mill sweep job', 'POST', '/v1/jobs',
    json({ analysis: 'tandem_sweep', tandem: twoStands, options: { parameter: '/speed_m_per_s', values: [10, 12], quantity: 'stability' } }), 202],
  ['mill map of stability', 'POST', '/v1/tandem/maps',
    json({ tandem: twoStands, options: { quantity: 'stability', parameters: [
      { parameter: '/speed_m_per_s', values: [8, 14] }, { parameter: '/spans/tension_MPa/0', values: [40, 80] }] } }), 200,
    every(equals('/result/cells/3/values/1', 80), equals('/result/parameters/0/unit', 'm/s'))],
  ['mill map of critical speeds', 'POST', '/v1/tandem/maps',
    json({ tandem: twoStands, options: { parameters: [
      { parameter: '/spans/length_m/0', values: [4] }, { parameter: '/spans/tension_MPa/0', values: [60] }],
      critical_speed: { speed_min_m_per_s: 5, speed_max_m_per_s: 20 } } }), 200,
    equals('/result/cells/0/kind', 'nominal_delay')],
  ['mill map csv', 'POST', '/v1/tandem/maps',
    { ...json({ tandem: twoStands, options: { quantity: 'stability', parameters: [
      { parameter: '/speed_m_per_s', values: [10] }, { parameter: '/spans/length_m/0', values: [4, 6] }] } }), accept: 'text/csv' }, 200],
  ['mill map bad value', 'POST', '/v1/tandem/maps',
    json({ tandem: twoStands, options: { quantity: 'stability', parameters: [
      { parameter: '/speed_m_per_s', values: [10] }, { parameter: '/spans/length_m/0', values: [-1] }] } }), 422,
    equals('/errors/0/pointer', '/options/parameters/1/values/0')],
  ['mill map job', 'POST', '/v1/jobs',
    json({ analysis: 'tandem_map', tandem: twoStands, options: { quantity: 'stability', parameters: [
      { parameter: '/speed_m_per_s', values: [10, 12] }, { parameter: '/spans/length_m/0', values: [4, 6] }] } }), 202],
  // plant units: the keys beside the canonical members, an atypical value's warning
  ['plant units', 'POST', '/v1/roll-gap',
    json({ scenario: { rolls: { speed_m_per_min: 900, diameter_mm: 560 }, lubricant: { viscosity_mPa_s: 0.8 } } }), 200,
    every(equals('/scenario/rolls/speed_m_per_s', 15), equals('/scenario/rolls/radius_mm', 280))],
  ['plant units, a mill', 'POST', '/v1/tandem',
    json({ tandem: { ...twoStands, speed_m_per_min: 720 }, options: { critical_speed: false } }), 200,
    equals('/tandem/speed_m_per_s', 12)],
  ['tensions in kN', 'POST', '/v1/roll-gap',
    json({ scenario: { tension: { back: { force_kN: 144 } } }, options: { distributions: false } }), 200,
    near('/scenario/tension/back/stress_MPa', 144e3 / (1.8 * 1.6e-3) / 1e6, 1e-12)],
  ['a mill\'s span tensions in kN', 'POST', '/v1/tandem',
    json({ tandem: { ...twoStands, spans: { length_m: [5], tension_kN: [90] } }, options: { critical_speed: false } }), 200,
    near('/tandem/spans/tension_MPa/0', 90e3 / (1.8 * 1.88e-3) / 1e6, 1e-12)],
  ['plant-unit CSV', 'POST', '/v1/sweeps?units=plant',
    { ...json({ options: { parameter: '/lubricant/viscosity_Pa_s', values: [0.0004] } }), accept: 'text/csv' }, 200],
  ['atypical value warned', 'POST', '/v1/roll-gap',
    json({ scenario: { rolls: { speed_m_per_s: 90 } } }), 200,
    equals('/warnings/0/likely/key', 'speed_m_per_min')],
  ['two forms of one member', 'POST', '/v1/roll-gap',
    json({ scenario: { rolls: { speed_m_per_s: 15, speed_m_per_min: 900 } } }), 422],
  // "absent or null: the defaults" (the document's words) also for the readers
  ['sweep critical speed null', 'POST', '/v1/sweeps',
    json({ options: { parameter: '/lubricant/viscosity_Pa_s', values: [0.0004], critical_speed: null, amplitude: null } }), 200],
  ['sweep amplitude null', 'POST', '/v1/sweeps',
    json({ options: { parameter: '/rolls/speed_m_per_s', values: [10], quantity: 'amplitude', amplitude: null, critical_speed: null } }), 200],
  ['calibrate nulls', 'POST', '/v1/calibrate',
    json({ options: { parameters: [{ field: '/strip/flow_stress_MPa', prior: null }], joint_prior: null, observations: [
      { scenario: null, quantity: 'roll_force_kN', value: 9000, standard_uncertainty: 60 }] } }), 200],
  // an empty body is the request {} (the document declares the body optional where {} is valid)
  ['empty body', 'POST', '/v1/stability', {}, 200],
  ['empty body, options required', 'POST', '/v1/sweeps', {}, 422],
  // strict Accept: what the route cannot answer with is a 406 problem
  ['accept xml', 'POST', '/v1/stability', { ...json({}), accept: 'application/xml' }, 406],
  ['job as csv', 'POST', '/v1/jobs', { ...json({ analysis: 'roll_gap' }), accept: 'text/csv' }, 406],
  ['invalid json', 'POST', '/v1/roll-gap', { body: '{', headers: { 'Content-Type': 'application/json' } }, 400],
  ['not json', 'POST', '/v1/roll-gap', { body: '{}', headers: { 'Content-Type': 'text/plain' } }, 415],
  ['invalid scenario', 'POST', '/v1/roll-gap', json({ scenario: { strip: { reduction: 25 } } }), 422,
    equals('/errors/0/pointer', '/scenario/strip/reduction')],
  ['invalid options', 'POST', '/v1/stability', json({ options: { speed_step_m_per_s: 3 } }), 422],
  ['unknown analysis', 'POST', '/v1/jobs', json({ analysis: 'chatter' }), 422],
  ['too large', 'POST', '/v1/roll-gap', { body: `{"x": "${'a'.repeat(1100000)}"}`, headers: { 'Content-Type': 'application/json' } }, 413],
  ['no such route', 'GET', '/v1/nothing', {}, 404],
  ['method not allowed', 'GET', '/v1/roll-gap', {}, 405],
  ['no such job', 'GET', '/v1/jobs/0123456789abcdef0123456789abcdef', {}, 404],
  ['jobs bad limit', 'GET', '/v1/jobs?limit=0', {}, 422],
  ['jobs bad state', 'GET', '/v1/jobs?state=done', {}, 422],
];

// The jobs: create, poll to the end, read as JSON and CSV, delete.
async function jobCases(base, run) {
  const created = await run(['create job', 'POST', '/v1/jobs',
    json({ analysis: 'sweep', options: { parameter: '/lubricant/viscosity_Pa_s', values: [0.0004, 0.0007] } }), 202]);
  const id = created.json.id;
  let job = created.json;
  for (let i = 0; i < 600 && (job.state === 'queued' || job.state === 'running'); ++i) {
    await new Promise((resolve) => setTimeout(resolve, 100));
    job = (await run(['poll job', 'GET', `/v1/jobs/${id}`, {}, 200])).json;
  }
  if (job.state !== 'succeeded') throw new Error(`job ended ${job.state}`);
  await run(['finished job', 'GET', `/v1/jobs/${id}`, {}, 200, equals('/result/analysis', 'sweep')]);
  await run(['finished job csv', 'GET', `/v1/jobs/${id}`, { accept: 'text/csv' }, 200]);
  await run(['finished job events', 'GET', `/v1/jobs/${id}/events`, { accept: 'text/event-stream' }, 200]);
  await run(['delete job', 'DELETE', `/v1/jobs/${id}`, {}, 200, equals('/deleted', true)]);
  await run(['deleted job', 'GET', `/v1/jobs/${id}`, {}, 404]);
  // An invalid scenario is refused at submission (422 problem), nothing stored (issue 17: it
  // used to be accepted and fail later).
  await run(['invalid job', 'POST', '/v1/jobs', json({ analysis: 'roll_gap', scenario: { strip: { reduction: 25 } } }), 422,
    equals('/errors/0/pointer', '/scenario/strip/reduction')]);
  const keyed = (body) => ({ ...json(body), headers: { ...json(body).headers, 'Idempotency-Key': 'contract-1' } });
  const first = await run(['keyed job', 'POST', '/v1/jobs', keyed({ analysis: 'roll_gap' }), 202]);
  await run(['keyed job again', 'POST', '/v1/jobs', keyed({ analysis: 'roll_gap' }), 200, equals('/id', first.json.id)]);
  await run(['keyed job other body', 'POST', '/v1/jobs', keyed({ analysis: 'stability' }), 409]);
  // Labels and a retention of its own; the list filtered by a label.
  const labelled = await run(['labelled job', 'POST', '/v1/jobs',
    json({ analysis: 'roll_gap', labels: { coil: 'C-4711' }, retention_s: 3600 }), 202,
    every(equals('/labels/coil', 'C-4711'), equals('/retention_s', 3600))]);
  await run(['jobs by label', 'GET', '/v1/jobs?label=coil:C-4711', {}, 200, equals('/jobs/0/labels/coil', 'C-4711')]);
  await run(['bad label', 'POST', '/v1/jobs', json({ analysis: 'roll_gap', labels: { '-x': 'y' } }), 422,
    equals('/errors/0/pointer', '/labels/-x')]);
  // The list: the newest job first; a state filter.
  await run(['list jobs', 'GET', '/v1/jobs?limit=1', {}, 200, equals('/jobs/0/id', labelled.json.id)]);
  await run(['list succeeded jobs', 'GET', '/v1/jobs?state=succeeded', {}, 200]);
  // every answer's echo is a request the same route takes (calibrate's holds "prior": null)
  const calibrated = await run(['calibrate to echo', 'POST', '/v1/calibrate',
    json({ options: { parameters: [{ field: '/strip/flow_stress_MPa' }], observations: [
      { quantity: 'roll_force_kN', value: 9000, standard_uncertainty: 60 }] } }), 200]);
  await run(['calibrate echo', 'POST', '/v1/calibrate',
    json({ scenario: calibrated.json.scenario, options: calibrated.json.options }), 200,
    equals('/result/parameters/0/value', calibrated.json.result.parameters[0].value)]);
}

// The stored scenarios on the service's own fresh store: create, read, list, the
// preconditions, validation, base in a request, delete.
async function scenarioCases(run) {
  const put = (body, headers = {}) => ({ body: JSON.stringify(body), headers: { 'Content-Type': 'application/json', ...headers } });
  await run(['create scenario', 'PUT', '/v1/scenarios/stand-1', put({ rolls: { speed_m_per_s: 12 } }, { 'If-None-Match': '*' }), 201,
    equals('/rolls/speed_m_per_s', 12)]);
  await run(['list scenarios', 'GET', '/v1/scenarios', {}, 200, equals('/scenarios/0/version', 1)]);
  await run(['get scenario', 'GET', '/v1/scenarios/stand-1', {}, 200, equals('/rolls/speed_m_per_s', 12)]);
  await run(['replace without If-Match', 'PUT', '/v1/scenarios/stand-1', put({}), 428]);
  await run(['replace with a stale If-Match', 'PUT', '/v1/scenarios/stand-1', put({}, { 'If-Match': '"9"' }), 412]);
  await run(['replace', 'PUT', '/v1/scenarios/stand-1', put({ rolls: { speed_m_per_s: 14 } }, { 'If-Match': '"1"' }), 200]);
  await run(['invalid stored scenario', 'PUT', '/v1/scenarios/stand-2', put({ strip: { reduction: 25 } }), 422,
    equals('/errors/0/pointer', '/strip/reduction')]);
  await run(['bad scenario name', 'PUT', '/v1/scenarios/-x', put({}), 422]);
  await run(['roll gap on a base', 'POST', '/v1/roll-gap', json({ base: 'stand-1', options: { distributions: false } }), 200,
    every(equals('/base/name', 'stand-1'), equals('/base/version', 2), equals('/scenario/rolls/speed_m_per_s', 14))]);
  await run(['unknown base', 'POST', '/v1/stability', json({ base: 'stand-9' }), 422, equals('/errors/0/pointer', '/base')]);
  await run(['delete scenario', 'DELETE', '/v1/scenarios/stand-1', { headers: { 'If-Match': '"2"' } }, 204]);
  await run(['deleted scenario', 'GET', '/v1/scenarios/stand-1', {}, 404]);
  // Stored mills: the same rules over the tandem document, base in a tandem request.
  const twoStands = { entry_thickness_mm: 1.88, exit_thickness_mm: [1.6, 1.36],
    spans: { length_m: [5], tension_MPa: [60] }, stands: [{}, {}] };
  await run(['default mill', 'GET', '/v1/mills/default', {}, 200]);
  await run(['create mill', 'PUT', '/v1/mills/line-2', put(twoStands, { 'If-None-Match': '*' }), 201,
    equals('/spans/tension_MPa/0', 60)]);
  await run(['list mills', 'GET', '/v1/mills', {}, 200, equals('/mills/0/name', 'line-2')]);
  await run(['get mill', 'GET', '/v1/mills/line-2', {}, 200, equals('/exit_thickness_mm/1', 1.36)]);
  await run(['invalid stored mill', 'PUT', '/v1/mills/line-3', put({ stands: [{ rolls: { radius_mm: -5 } }] }), 422]);
  await run(['mill over a stand', 'PUT', '/v1/mills/stand-2', put(twoStands), 201]);
  await run(['stand over a mill', 'PUT', '/v1/scenarios/stand-2', put({}), 409]);
  await run(['tandem on a base', 'POST', '/v1/tandem', json({ base: 'line-2', options: { critical_speed: false } }), 200,
    every(equals('/base/name', 'line-2'), equals('/tandem/exit_thickness_mm/1', 1.36))]);
  await run(['delete mill', 'DELETE', '/v1/mills/line-2', { headers: { 'If-Match': '"1"' } }, 204]);
}

function templateMatch(template, path) {
  const pattern = new RegExp(`^${template.replace(/\{[^}]+\}/g, '[^/]+')}$`);
  return pattern.test(path.split('?')[0]);
}

// A data directory whose database path is a directory
// (the store unavailable).
const dataDir = mkdtempSync(join(tmpdir(), 'rollgap-contract-'));
mkdirSync(join(dataDir, 'broken.db'));
const service = await startService(binary);  // a fresh data directory of its own (service.mjs)
const broken = await startService(binary, ['--store', `sqlite:${join(dataDir, 'broken.db')}`]);
let validated = 0;
const failures = [];
try {
  const document = await (await fetch(`${service.base}/openapi.json`)).json();
  const ajv = new Ajv2020({ strict: false, allErrors: true });
  addFormats(ajv);
  ajv.addSchema(document, 'openapi');
  const escape = (segment) => segment.replace(/~/g, '~0').replace(/\//g, '~1');

  const runAt = (base) => async ([name, method, path, request, status, check]) => {
    const headers = { ...(request.headers || {}) };
    if (request.accept) headers.Accept = request.accept;
    const response = await fetch(`${base}${path}`, { method, headers, body: request.body });
    const header = (name) => response.headers.get(name);
    const text = await response.text();
    const type = (response.headers.get('content-type') || '').split(';')[0].trim();
    const outcome = { text, json: undefined };
    try {
      if (response.status !== status) throw new Error(`status ${response.status}, expected ${status}: ${text.slice(0, 300)}`);
      const template = Object.keys(document.paths).find((t) => templateMatch(t, path));
      let declared;
      let pointer;
      if (template) {
        const operation = document.paths[template][method.toLowerCase()];
        if (operation) {
          declared = operation.responses[String(response.status)];
          pointer = `#/paths/${escape(template)}/${method.toLowerCase()}/responses/${response.status}`;
        } else if (response.status === 405) {
          // A method the path does not have has no operation to declare it: a problem.
          declared = { content: { 'application/problem+json': { schema: { $ref: '#/components/schemas/Problem' } } } };
          pointer = undefined;
        } else {
          throw new Error(`${method} ${template} is not in the document`);
        }
      } else {
        // Unknown paths: the document's NotFound response.
        declared = { $ref: '#/components/responses/NotFound' };
      }
      if (!declared) throw new Error(`status ${response.status} is not declared for ${method} ${template}`);
      const operation = template ? document.paths[template][method.toLowerCase()] : undefined;
      // A request the service answered 2xx is one the document admits: its body validates
      // against the declared request schema, and a missing body is declared optional.
      if (operation && response.status < 300 && (method === 'POST' || method === 'PUT' || method === 'PATCH')) {
        const body = operation.requestBody;
        if (request.body === undefined) {
          if (body?.required) throw new Error('answered without a body, but the document requires one');
        } else {
          const media = Object.keys(body?.content || {})[0];
          const check = ajv.getSchema(`openapi#/paths/${escape(template)}/${method.toLowerCase()}/requestBody/content/${escape(media)}/schema`);
          if (!check(JSON.parse(request.body))) {
            throw new Error(`the request was answered ${response.status} but the document refuses it: ${ajv.errorsText(check.errors)}`);
          }
        }
      }
      // Headers: the request id on every answer, declared; the poll hint on every 202; Vary on
      // what answers JSON or CSV.
      let resolvedResponse = declared;
      while (resolvedResponse.$ref) resolvedResponse = resolvedResponse.$ref.split('/').slice(1).reduce((node, key) => node[key], document);
      if (!header('x-request-id')) throw new Error('no X-Request-Id');
      if (operation && !resolvedResponse.headers?.['X-Request-Id']) throw new Error(`X-Request-Id not declared for ${response.status}`);
      if (response.status === 202) {
        if (!header('retry-after')) throw new Error('a 202 without Retry-After');
        if (!resolvedResponse.headers?.['Retry-After']) throw new Error('Retry-After not declared on the 202');
      }
      const csvDeclared = Boolean(operation?.responses?.['200']?.content?.['text/csv']);
      if (csvDeclared !== ((header('vary') || '').includes('Accept'))) {
        throw new Error(`Vary: ${header('vary')} where the operation ${csvDeclared ? 'answers' : 'does not answer'} CSV`);
      }
      if ((header('connection') || '').split(',').length > 1) throw new Error(`Connection: ${header('connection')}`);
      while (declared.$ref) {
        pointer = declared.$ref;
        declared = declared.$ref.split('/').slice(1).reduce((node, key) => node[key.replace(/~1/g, '/').replace(/~0/g, '~')], document);
      }
      if (response.status === 204) {
        if (text !== '') throw new Error('204 with a body');
      } else {
        const media = declared.content?.[type];
        if (!media) throw new Error(`content type ${type} is not declared for ${response.status} (${Object.keys(declared.content || {})})`);
        if (type.endsWith('json')) {
          outcome.json = JSON.parse(text);
          const validate = pointer ? ajv.getSchema(`openapi${pointer}/content/${escape(type)}/schema`)
            : ajv.getSchema('openapi#/components/schemas/Problem');
          if (!validate(outcome.json)) throw new Error(ajv.errorsText(validate.errors, { separator: '\n  ' }));
        } else if (type === 'text/csv') {
          const lines = text.split('\r\n');
          if (lines.at(-1) !== '' || lines.length < 3) throw new Error('CSV without a header and a row, or not CRLF-terminated');
          const width = lines[0].split(',').length;
          if (lines.slice(1, -1).some((line) => line.split(',').length !== width)) throw new Error('ragged CSV');
        }
      }
      if (check) check(outcome.json);
      ++validated;
    } catch (error) {
      failures.push(`${name} (${method} ${path}): ${error.message}`);
    }
    return outcome;
  };

  const run = runAt(service.base);
  for (const row of cases) await run(row);
  await jobCases(service.base, run);
  await scenarioCases(run);
  const onBroken = runAt(broken.base);
  await onBroken(['scenarios, store down', 'GET', '/v1/scenarios', {}, 503]);
  await onBroken(['base, store down', 'POST', '/v1/roll-gap', json({ base: 'stand-1' }), 503]);
  await onBroken(['no base, store down', 'POST', '/v1/roll-gap', json({ options: { distributions: false } }), 200]);
} finally {
  await service.stop();
  await broken.stop();
  rmSync(dataDir, { recursive: true, force: true });
}
const routes = new Set(cases.map(([, method, path]) => `${method} ${path.split('?')[0]}`));
console.log(`validated ${validated} responses against the served /openapi.json (${routes.size} method+path pairs, plus jobs)`);
if (failures.length > 0) {
  console.error(`${failures.length} failed:\n- ${failures.join('\n- ')}`);
  process.exit(1);
}
