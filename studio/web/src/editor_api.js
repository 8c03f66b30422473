// The editor's requests to cobra's server (studio/PROTOCOL.md "The editor (v1)"), with the page's
// token as the console sends it (source.js). An answer that is not 2xx throws an ApiError with the
// server's `error` text (cobra's own line) and the whole body (a 422 from open names the line).
import { pageToken } from './source.js';

export class ApiError extends Error {
  constructor(message, status, body) {
    super(message);
    this.status = status;
    this.body = body;
  }
}

/** Sends `body` (JSON) with `method` to `path`; resolves to the answer's JSON. */
export async function request(method, path, body) {
  const url = new URL(path, window.location.href);
  const token = pageToken();
  if (token) url.searchParams.set('token', token);
  let response;
  try {
    response = await fetch(url, {
      method,
      headers: { 'X-Cobra-Token': token, ...(body === undefined ? {} : { 'Content-Type': 'application/json' }) },
      body: body === undefined ? undefined : JSON.stringify(body),
    });
  } catch (err) {
    throw new ApiError(`${path}: the cobra server cannot be reached (${err.message})`, 0, null);
  }
  const text = await response.text();
  let answer;
  try {
    answer = JSON.parse(text);
  } catch {
    throw new ApiError(`${path}: HTTP ${response.status}: expected JSON, got ${JSON.stringify(text.slice(0, 120))}`, response.status, null);
  }
  if (!response.ok) throw new ApiError(answer.error ?? `${path}: HTTP ${response.status} without an error text`, response.status, answer);
  return answer;
}

export const api = {
  palette: () => request('GET', 'api/editor/palette'),
  project: () => request('GET', 'api/editor/project'),
  open: (path) => request('POST', 'api/editor/open', { path }),
  check: (project, connection) => request('POST', 'api/editor/check', { project, connection }),
  validate: (project) => request('POST', 'api/editor/validate', { project }),
  save: (path, project) => request('POST', 'api/editor/save', { path, project }),
  generate: (folder, component) => request('POST', 'api/editor/generate', { folder, component }),
  running: () => request('GET', 'api/editor/running'),
};
