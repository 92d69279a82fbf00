// Client of the JSON API in docs/http-api.md. Every failure becomes an ApiError whose message
// is the service's own when it sent one, so the page can show it to the shopper verbatim.

class ApiError extends Error {
  constructor(message, { status = 0, code = 'UNKNOWN' } = {}) {
    super(message);
    this.name = 'ApiError';
    this.status = status;
    this.code = code;
  }
}

// getKey is read on every call: the key can change (URL fragment, key field) while the page
// is open, and is kept in memory only.
export function createApi(getKey) {
  async function call(method, path, { json, body, contentType } = {}) {
    const headers = {};
    const key = getKey();
    // No header at all rather than an empty one, so the server answers "missing key".
    if (key) headers['X-Api-Key'] = key;
    if (json !== undefined) {
      headers['Content-Type'] = 'application/json';
      body = JSON.stringify(json);
    } else if (contentType) {
      headers['Content-Type'] = contentType;
    }

    let response;
    try {
      response = await fetch(path, { method, headers, body, cache: 'no-store' });
    } catch (e) {
      throw new ApiError(`Could not reach the fit service (${e.message}).`, { code: 'UNAVAILABLE' });
    }
    const text = await response.text();
    let data = null;
    try {
      data = JSON.parse(text);
    } catch {
      // Not JSON: a proxy's error page, say. Reported below with the HTTP status.
    }
    if (!response.ok) {
      const error = data?.error;
      throw new ApiError(error?.message || `The fit service answered HTTP ${response.status}.`, {
        status: response.status,
        code: error?.code || 'UNKNOWN',
      });
    }
    if (data === null) {
      throw new ApiError('The fit service sent an answer that is not JSON.', { status: response.status });
    }
    return data;
  }

  const population = (p) => `population=${encodeURIComponent(p)}`;
  return {
    listGarments: () => call('GET', '/api/v1/garments'),
    garmentTopology: (id) => call('GET', `/api/v1/garments/${encodeURIComponent(id)}/topology`),
    bodyTopology: (p) => call('GET', `/api/v1/bodies/topology?${population(p)}`),
    // file: a File or Blob. An OBJ is text, a .fba (fitbase avatar) binary. The answer's body
    // is the upload itself (Draco), which fit() sends back so the garment is fitted to it.
    projectBody: (p, file, isFba) =>
      call('POST', `/api/v1/bodies/project?${population(p)}&body=own`, {
        body: file,
        contentType: isFba ? 'application/octet-stream' : 'text/plain',
      }),
    bodyFromMeasurements: (p, measurements) =>
      call('POST', '/api/v1/bodies/from-measurements', { json: { population: p, measurements } }),
    // weights exactly as the body endpoint answered them: the basis id travels with them.
    // body: the shopper's own mesh (an Avatar) to fit to, or null for the body of the weights.
    fit: (weights, garmentId, body) =>
      call('POST', '/api/v1/fit', { json: { weights, garment_id: garmentId, ...(body ? { body } : {}) } }),
  };
}
