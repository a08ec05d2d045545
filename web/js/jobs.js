// Long work as a job: POST /v1/jobs, poll its progress (and, for chunked sweeps and maps, the
// finished points), cancel it. The recent jobs come from GET /v1/jobs when the service offers
// it (its OpenAPI document lists the operation and it does not answer 404); otherwise from the
// ids this browser remembered.
import { ProblemError, call, getJson } from './api.js';

const KEY = 'rollgap.jobs';
const localJobs = () => { try { return JSON.parse(localStorage.getItem(KEY)) || []; } catch { return []; } };
function remember(job) {
  const list = [job, ...localJobs().filter((j) => j.id !== job.id)].slice(0, 10);
  localStorage.setItem(KEY, JSON.stringify(list));
}

// The service's job list, newest first: { jobs, next_cursor }; null when it has none.
let serverList = null;  // unknown until the document is read
export function useServerJobList(doc) { serverList = Boolean(doc.paths['/v1/jobs'] && doc.paths['/v1/jobs'].get); }

export async function recentJobs(cursor) {
  if (serverList) {
    try {
      const query = new URLSearchParams({ limit: '20' });
      if (cursor) query.set('cursor', cursor);
      const page = await getJson(`/v1/jobs?${query}`);
      return { jobs: page.jobs || [], next: page.next_cursor || null, source: 'service' };
    } catch (error) {
      if (!(error instanceof ProblemError) || (error.status !== 404 && error.status !== 405)) throw error;
      serverList = false;
    }
  }
  return { jobs: localJobs(), next: null, source: 'browser' };
}

export class JobRunner {
  constructor({ onProgress }) { this.onProgress = onProgress; this.current = null; }

  async run(request) {
    const { location, body } = await call('POST', '/v1/jobs', request);
    const path = location || `/v1/jobs/${body.id}`;
    remember({ id: body.id, analysis: request.analysis, created_at: body.created_at });
    this.current = path;
    try {
      for (;;) {
        const job = await getJson(path);
        this.onProgress(job, request);
        if (['succeeded', 'failed', 'cancelled'].includes(job.state)) return job;
        await new Promise((resolve) => setTimeout(resolve, 250));
      }
    } finally { this.current = null; }
  }

  async cancel() { if (this.current) await call('DELETE', this.current); }
}

export const openJob = (id) => getJson(`/v1/jobs/${encodeURIComponent(id)}`);
