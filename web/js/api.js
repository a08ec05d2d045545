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

function send(method, path, body, accept, extra = {}) {
  const headers = { Accept: accept, ...extra };
  if (token()) headers.Authorization = `Bearer ${token()}`;
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  return fetch(path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
}
const parsed = (text) => {
  try { return text ? JSON.parse(text) : null; } catch { return { detail: text }; }
};

// `headers`: more request headers (If-Match, If-None-Match of a stored mill's PUT).
export async function call(method, path, body, headers) {
  const response = await send(method, path, body, 'application/json', headers);
  const document = parsed(await response.text());
  if (!response.ok) throw new ProblemError(response.status, document);
  return { status: response.status, location: response.headers.get('Location'), etag: response.headers.get('ETag'), body: document };
}

// The body in another media type (`accept`, e.g. text/csv) as the service wrote it, byte for
// byte; a problem is an error as in call().
export async function fetchBlob(method, path, body, accept) {
  const response = await send(method, path, body, accept);
  if (!response.ok) throw new ProblemError(response.status, parsed(await response.text()));
  return response.blob();
}

export const getJson = async (path) => (await call('GET', path)).body;
