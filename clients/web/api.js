// The hexcover HTTP API, version 1 (api/openapi.json), as used by the page.

/** An error response: `problem` is the RFC 9457 document (title, status, detail, ...). */
export class ApiError extends Error {
  constructor(problem) {
    super(problem.detail || problem.title || `HTTP ${problem.status}`);
    this.problem = problem;
  }
}

async function problemOf(response) {
  try {
    return await response.json();
  } catch {
    return { status: response.status, title: response.statusText };
  }
}

async function getJson(url) {
  const response = await fetch(url, { headers: { Accept: 'application/json' } });
  if (!response.ok) throw new ApiError(await problemOf(response));
  return response.json();
}

export const kTerminalStates = new Set(['succeeded', 'failed', 'canceled']);

/**
 * POST /v1/jobs as multipart/form-data with the file in part `mesh`, options as query parameters
 * (edge_length, vertices, rosy, sizing, placement, feature_angle, d_sing).
 * onProgress(sentBytes, totalBytes) follows the upload. Resolves to the job document of the 202 answer.
 */
export function submitJob(file, options, onProgress) {
  const query = new URLSearchParams();
  for (const [name, value] of Object.entries(options)) {
    if (value !== undefined && value !== null && value !== '') query.set(name, String(value));
  }
  const form = new FormData();
  form.append('mesh', file, file.name);
  return new Promise((resolve, reject) => {
    const xhr = new XMLHttpRequest();
    xhr.open('POST', `/v1/jobs?${query}`);
    xhr.responseType = 'json';
    xhr.setRequestHeader('Accept', 'application/json');
    xhr.upload.onprogress = (event) => onProgress(event.loaded, event.lengthComputable ? event.total : file.size);
    xhr.onload = () => {
      if (xhr.status === 202 || xhr.status === 200) resolve(xhr.response);
      else reject(new ApiError(xhr.response ?? { status: xhr.status, title: xhr.statusText }));
    };
    xhr.onerror = () => reject(new ApiError({ status: 0, title: 'network error during upload' }));
    xhr.send(form);
  });
}

export const getJob = (id) => getJson(`/v1/jobs/${encodeURIComponent(id)}`);
export const getMetrics = (id) => getJson(`/v1/jobs/${encodeURIComponent(id)}/metrics`);

export async function cancelJob(id) {
  const response = await fetch(`/v1/jobs/${encodeURIComponent(id)}`, { method: 'DELETE' });
  if (!response.ok && response.status !== 404) throw new ApiError(await problemOf(response));
}

/** URL of a result: format obj|ply|off|stl|glb, mesh triangles|hexagons|textured. */
export function resultUrl(id, format, mesh) {
  return `/v1/jobs/${encodeURIComponent(id)}/result?format=${format}&mesh=${mesh}`;
}

export async function fetchResult(id, format, mesh) {
  const response = await fetch(resultUrl(id, format, mesh));
  if (!response.ok) throw new ApiError(await problemOf(response));
  return response.arrayBuffer();
}

/**
 * Polls GET /v1/jobs/{id} until the job reaches a terminal state, calling onUpdate(job) with each
 * document. Resolves to the last document.
 */
export async function waitForJob(id, onUpdate, intervalMs = 400) {
  for (;;) {
    const job = await getJob(id);
    onUpdate(job);
    if (kTerminalStates.has(job.state)) return job;
    await new Promise((resolve) => setTimeout(resolve, intervalMs));
  }
}
