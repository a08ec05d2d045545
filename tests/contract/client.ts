// A small MES-style client on the types openapi-typescript generates from the served document
// (rollgap-api.d.ts, generated next to this file by typescript_client.mjs). It must type-check
// under `tsc --strict`: the responses are typed, not `Record<string, never>`.
import type { components, paths } from './rollgap-api';

type Json<P extends keyof paths, M extends 'post' | 'get'> = paths[P][M] extends {
  responses: { 200: { content: { 'application/json': infer Body } } };
}
  ? Body
  : never;

type StabilityAnswer = Json<'/v1/stability', 'post'>;
type SweepAnswer = Json<'/v1/sweeps', 'post'>;
type Job = components['schemas']['Job'];

// Type-level checks: a member typed `never` (an untyped response) fails them.
type Assert<T extends true> = T;
type Exactly<A, B> = [A] extends [B] ? ([B] extends [A] ? true : false) : false;
export type CriticalSpeedIsANumber = Assert<
  Exactly<NonNullable<StabilityAnswer['result']['critical_speed']>['critical_speed_m_per_s'], number | null>
>;
export type SweepStatusIsTyped = Assert<Exactly<SweepAnswer['result']['quantity'], 'critical_speed' | 'amplitude'>>;

export function criticalSpeed(answer: StabilityAnswer): number | null {
  const search = answer.result.critical_speed;
  return search === null ? null : search.critical_speed_m_per_s;
}

export function describeSweep(answer: SweepAnswer): string[] {
  return answer.result.points.map((point) => {
    const value = (point as Record<string, unknown>)[answer.result.value_name];
    if ('critical_speed_m_per_s' in point) {
      const speed: number | null = point.critical_speed_m_per_s;
      return `${answer.result.parameter} = ${String(value)} ${answer.result.unit}: ${point.status}, ${speed ?? '-'} m/s`;
    }
    const amplitude: number | null = point.upper_roll_amplitude_um;
    return `${answer.result.parameter} = ${String(value)}: ${point.status}, ${amplitude ?? '-'} um`;
  });
}

export function jobCriticalSpeed(job: Job): number | null {
  if (job.state !== 'succeeded' || job.result === undefined) return null;
  const answer = job.result;
  switch (answer.analysis) {
    case 'stability':
      return answer.result.critical_speed?.critical_speed_m_per_s ?? null;
    case 'evaluate':
      return answer.result.critical_speed.critical_speed_m_per_s;
    case 'sweep':
      return answer.result.points.length;
    default:
      return null;
  }
}
