// Stored scenarios (GET /v1/scenarios, GET /v1/scenarios/{name}) and stored tandem mills
// (GET /v1/mills, GET and PUT /v1/mills/{name}), used when the service offers them: its OpenAPI
// document lists the operation and the list does not answer 404. A request then names its base
// (`base`) and carries only the differences from it.
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

export const offersStoredMills = (doc) => Boolean(doc.paths['/v1/mills'] && doc.paths['/v1/mills'].get);

// [{ name, version, updated_at }] of the stored mills, or null when the service has none.
export async function storedMills(doc) {
  if (!offersStoredMills(doc)) return null;
  try {
    return (await getJson('/v1/mills')).mills || [];
  } catch (error) {
    if (error instanceof ProblemError && (error.status === 404 || error.status === 405)) return null;
    throw error;
  }
}

// The stored mill (resolved: its fields and each stand's complete scenario) and its version.
export async function storedMill(name) {
  const { body, etag } = await call('GET', `/v1/mills/${encodeURIComponent(name)}`);
  return { mill: body, version: etag || '' };
}

// Stores `mill` (a merge patch onto the default mill; a complete mill is one) under `name`:
// `version` (the ETag of the mill loaded under that name) replaces it, none creates it only
// (If-None-Match: *, so a name someone else holds is never overwritten: 412).
export async function saveMill(name, mill, version) {
  const headers = version ? { 'If-Match': version } : { 'If-None-Match': '*' };
  const { etag } = await call('PUT', `/v1/mills/${encodeURIComponent(name)}`, mill, headers);
  return etag || '';
}
