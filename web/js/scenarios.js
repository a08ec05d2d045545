// Stored scenarios (GET /v1/scenarios, GET /v1/scenarios/{name}), used when the service offers
// them: its OpenAPI document lists the operation and the list does not answer 404. A request
// then names its base (`base`) and carries only the differences from it.
import { ProblemError, call, getJson } from './api.js';

export const offersStoredScenarios = (doc) => Boolean(doc.paths['/v1/scenarios'] && doc.paths['/v1/scenarios'].get);

// [{ name, version, updated_at }], or null when the service has no stored scenarios.
export async function storedScenarios(doc) {
  if (!offersStoredScenarios(doc)) return null;
  try {
    return (await getJson('/v1/scenarios')).scenarios || [];
  } catch (error) {
    if (error instanceof ProblemError && (error.status === 404 || error.status === 405)) return null;
    throw error;
  }
}

// The full scenario and its version (the ETag).
export async function storedScenario(name) {
  const { body, etag } = await call('GET', `/v1/scenarios/${encodeURIComponent(name)}`);
  return { scenario: body, version: etag || '' };
}
