// Requests an MES client writes, typed by openapi-typescript's default output of the served
// document (rollgap-api.d.ts, generated next to this file by typescript_client.mjs). Under
// `tsc --strict` each must type-check: a merge patch that names one field, a sweep that gives
// only what it must, a job and a batch item without every option. A member with a `default`
// would be required by the generated type, so request bodies carry none (the answers do).
import type { paths } from './rollgap-api';

type Body<P extends keyof paths, M extends 'post' | 'put' | 'patch', Media extends string = 'application/json'> =
  NonNullable<paths[P][M]> extends { requestBody?: infer B }
    ? NonNullable<B> extends { content: { [K in Media]: infer T } }
      ? T
      : never
    : never;

// PATCH /v1/scenarios/{name}: one field, the rest stays as stored.
export const speedOnly: Body<'/v1/scenarios/{name}', 'patch', 'application/merge-patch+json'> = {
  rolls: { speed_m_per_s: 15 },
};
// Plant units: the speed in m/min, the roll's diameter, the viscosity in mPa·s.
export const plantUnits: Body<'/v1/scenarios/{name}', 'patch', 'application/merge-patch+json'> = {
  rolls: { speed_m_per_min: 900, diameter_mm: 560 },
  lubricant: { viscosity_mPa_s: 0.8 },
};
// Tensions in kN: the force over the strip's cross-section on that side, echoed as the stress.
export const tensionForces: Body<'/v1/scenarios/{name}', 'patch', 'application/merge-patch+json'> = {
  tension: { back: { force_kN: 150 }, front: { force_kN: 200, stress_MPa: null } },
};
// null restores a field's default in a merge patch.
export const restoreViscosity: Body<'/v1/scenarios/{name}', 'patch', 'application/merge-patch+json'> = {
  lubricant: { viscosity_Pa_s: null },
};
// PUT /v1/mills/{name}: a mill patch with two stands, each a partial stand.
export const twoStands: Body<'/v1/mills/{name}', 'put'> = {
  entry_thickness_mm: 2.25,
  exit_thickness_mm: [1.88, 1.6],
  stands: [{}, { rolls: { radius_mm: 250 } }],
};
// POST /v1/sweeps: the parameter and the values, nothing else.
export const sweep: Body<'/v1/sweeps', 'post'> = {
  scenario: { strip: { reduction: 0.3 } },
  options: { parameter: '/lubricant/viscosity_Pa_s', values: [0.0004, 0.0007] },
};
// POST /v1/stability: one option of several.
export const stability: Body<'/v1/stability', 'post'> = { options: { detail: 'summary' } };
// POST /v1/speed-limit: two limits of many.
export const speedLimit: Body<'/v1/speed-limit', 'post'> = {
  base: 'stand-3',
  options: { max_roll_force_kN: 12000, chatter_margin: 0.1 },
};
// POST /v1/jobs: an analysis with a partial scenario, the coil's labels, a day's retention and
// a completion callback.
export const job: Body<'/v1/jobs', 'post'> = {
  analysis: 'stability',
  scenario: { rolls: { speed_m_per_s: 12 } },
  labels: { coil: 'C-4711', line: 'TCM2' },
  retention_s: 86400,
  callback_url: 'https://mes.plant.example/hooks/rollgap',
};
// POST /v1/batches: coils, each a label and a partial patch.
export const batch: Body<'/v1/batches', 'post'> = {
  options: {
    analysis: 'speed_limit',
    base: 'stand-3',
    items: [
      { label: 'C-1', scenario: { strip: { flow_stress_MPa: 420 } } },
      { label: 'C-2' },
    ],
  },
  labels: { shift: 'night' },
};
