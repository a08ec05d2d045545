// Long work as a job: POST /v1/jobs, poll its progress, cancel it; recent jobs are remembered
// in this browser (ids only) so they can be reopened while the service keeps them.
import { call, getJson } from './api.js';

const KEY = 'rollgap.jobs';
export const recentJobs = () => { try { return JSON.parse(localStorage.getItem(KEY)) || []; } catch { return []; } };
function remember(job) {
  const list = [job, ...recentJobs().filter((j) => j.id !== job.id)].slice(0, 10);
  localStorage.setItem(KEY, JSON.stringify(list));
}

export class JobRunner {
  constructor({ onProgress }) { this.onProgress = onProgress; this.current = null; }

  async run(request) {
    const { location, body } = await call('POST', '/v1/jobs', request);
    const path = location || `/v1/jobs/${body.id}`;
    remember({ id: body.id, analysis: request.analysis, created_at: body.created_at, request });
    this.current = path;
    try {
      for (;;) {
        const job = await getJson(path);
        this.onProgress(job);
        if (['succeeded', 'failed', 'cancelled'].includes(job.state)) return job;
        await new Promise((resolve) => setTimeout(resolve, 250));
      }
    } finally { this.current = null; }
  }

  async cancel() { if (this.current) await call('DELETE', this.current); }
}

export const openJob = (id) => getJson(`/v1/jobs/${encodeURIComponent(id)}`);
