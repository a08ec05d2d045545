// Talking to the service: same origin, the bearer token (kept in sessionStorage, never in the
// URL) on every call, RFC 9457 problems turned into an error carrying the problem document.

const TOKEN_KEY = 'rollgap.token';

export function token() { return sessionStorage.getItem(TOKEN_KEY) || ''; }
export function setToken(value) {
  if (value) sessionStorage.setItem(TOKEN_KEY, value); else sessionStorage.removeItem(TOKEN_KEY);
}

export class ProblemError extends Error {
  constructor(status, problem) {
    super(problem && problem.detail ? problem.detail : `HTTP ${status}`);
    this.status = status;
    this.problem = problem || { status, detail: `HTTP ${status}` };
  }
}

export async function call(method, path, body) {
  const headers = { Accept: 'application/json' };
  if (token()) headers.Authorization = `Bearer ${token()}`;
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const response = await fetch(path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
  const text = await response.text();
  let document = null;
  try { document = text ? JSON.parse(text) : null; } catch { document = { detail: text }; }
  if (!response.ok) throw new ProblemError(response.status, document);
  return { status: response.status, location: response.headers.get('Location'), etag: response.headers.get('ETag'), body: document };
}

export const getJson = async (path) => (await call('GET', path)).body;
