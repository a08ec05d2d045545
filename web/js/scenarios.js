// Stored scenarios (GET /v1/scenarios, GET, PUT and PATCH /v1/scenarios/{name}) and stored tandem mills
// (GET /v1/mills, GET and PUT /v1/mills/{name}), used when the service offers them: its OpenAPI
// document lists the operation and the list does not answer 404. A request then names its base
// (`base`) and carries only the differences from it.
import { ProblemError, call, getJson } from './api.js';

// A stored collection the service offers at `path` (its OpenAPI document lists the GET):
// its list under `member`, [{ name, version, updated_at }], or null when it has none.
const offers = (doc, path) => Boolean(doc.paths[path] && doc.paths[path].get);
async function storedList(doc, path, member) {
  if (!offers(doc, path)) return null;
  try {
    return (await getJson(path))[member] || [];
  } catch (error) {
    if (error instanceof ProblemError && (error.status === 404 || error.status === 405)) return null;
    throw error;
  }
}

// One stored item (its body) and its version (the ETag).
async function storedItem(path, name) {
  const { body, etag } = await call('GET', `${path}/${encodeURIComponent(name)}`);
  return { body, version: etag || '' };
}

export const offersStoredScenarios = (doc) => offers(doc, '/v1/scenarios');
export const storedScenarios = (doc) => storedList(doc, '/v1/scenarios', 'scenarios');
// The full scenario and its version.
export async function storedScenario(name) {
  const { body, version } = await storedItem('/v1/scenarios', name);
  return { scenario: body, version };
}

// Stores `scenario` (a merge patch onto the default scenario; a complete scenario is one) under a
// new `name` only (If-None-Match: *: a name someone holds is never overwritten, 412); its version.
export async function createScenario(name, scenario) {
  const { etag } = await call('PUT', `/v1/scenarios/${encodeURIComponent(name)}`, scenario, { 'If-None-Match': '*' });
  return etag || '';
}
// Edits the stored stand `name`: `patch` (RFC 7396) merged onto the version `version` (its ETag)
// names, stored as the next; 412 when another write came in between. A PATCH, not a PUT: the
// stand keeps its calibration posterior unless a field it describes changes (docs/http-api.md).
export async function updateScenario(name, patch, version) {
  const { etag } = await call('PATCH', `/v1/scenarios/${encodeURIComponent(name)}`, patch, { 'If-Match': version });
  return etag || '';
}

export const offersStoredMills = (doc) => offers(doc, '/v1/mills');
export const storedMills = (doc) => storedList(doc, '/v1/mills', 'mills');
// The stored mill (resolved: its fields and each stand's complete scenario) and its version.
export async function storedMill(name) {
  const { body, version } = await storedItem('/v1/mills', name);
  return { mill: body, version };
}

// Stores `mill` (a merge patch onto the default mill; a complete mill is one) under `name`:
// `version` (the ETag of the mill loaded under that name) replaces it, none creates it only
// (If-None-Match: *, so a name someone else holds is never overwritten: 412).
export async function saveMill(name, mill, version) {
  const headers = version ? { 'If-Match': version } : { 'If-None-Match': '*' };
  const { etag } = await call('PUT', `/v1/mills/${encodeURIComponent(name)}`, mill, headers);
  return etag || '';
}
