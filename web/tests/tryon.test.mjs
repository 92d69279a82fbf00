// Tests of the try-on page and of the HTTP API's errors, against a running server:
//
//   node web/tests/tryon.test.mjs --server http://127.0.0.1:PORT --key KEY [--scan avatar.obj]
//     [--screenshot out.png]
//
// --scan: an avatar OBJ of the garments' population, uploaded as a shopper's scan.
//
// The browser is Debian's Chromium (/usr/bin/chromium) driven by playwright-core, rendering
// WebGL in software (SwiftShader), so the tests need no GPU and download no browser.
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { after, before, describe, test } from 'node:test';
import { parseArgs } from 'node:util';
import { chromium } from 'playwright-core';

const { values: args } = parseArgs({
  options: {
    server: { type: 'string' },
    key: { type: 'string' },
    screenshot: { type: 'string' },
    scan: { type: 'string' },
    chromium: { type: 'string', default: '/usr/bin/chromium' },
  },
});
if (!args.server || !args.key) {
  console.error('usage: node web/tests/tryon.test.mjs --server http://127.0.0.1:PORT --key KEY [--scan avatar.obj] [--screenshot out.png]');
  process.exit(2);
}
const SERVER = args.server.replace(/\/$/, '');
const KEY = args.key;
const MAX_BODY = 8 * 1024 * 1024;
// Fits of every size on a software renderer: generous, but a hang still fails.
const SETTLE_MS = 120_000;
const BAD_OBJ = 'v 1 2\nf 1 2 3\n';
const SKIN = '#d9a58a';

// An OBJ just over the request limit, made of valid lines so only its size is wrong.
function oversizedObj() {
  const line = 'v 0.000000 0.000000 0.000000\n';
  return Buffer.from(line.repeat(Math.ceil((MAX_BODY + 1024) / line.length)));
}

// ---- The API, from node --------------------------------------------------------------------

async function call(method, urlPath, { key = KEY, body, contentType } = {}) {
  const headers = {};
  if (key !== null) headers['X-Api-Key'] = key;
  if (contentType) headers['Content-Type'] = contentType;
  const response = await fetch(`${SERVER}${urlPath}`, { method, headers, body });
  const text = await response.text();
  let json = null;
  try {
    json = JSON.parse(text);
  } catch {
    // Checked by the caller: errors must be JSON.
  }
  return { status: response.status, json, text };
}

function assertError(answer, status, code) {
  assert.equal(answer.status, status, `HTTP ${answer.status}, wanted ${status}: ${answer.text.slice(0, 300)}`);
  assert.ok(answer.json?.error, `not a JSON error: ${answer.text.slice(0, 300)}`);
  if (code) assert.equal(answer.json.error.code, code);
  assert.equal(typeof answer.json.error.message, 'string');
  assert.ok(answer.json.error.message.length > 0, 'empty error message');
}

async function firstGarment() {
  const answer = await call('GET', '/api/v1/garments');
  assert.equal(answer.status, 200, answer.text.slice(0, 300));
  const [garment] = answer.json.garments ?? [];
  assert.ok(garment, 'the key\'s tenant has no garments to try on');
  return garment;
}

describe('HTTP API errors', { concurrency: 1 }, () => {
  // Looked up by the tests that need a population, so the others still run without one.
  let listed;
  const garment = () => (listed ??= firstGarment());

  test('a missing key is 401', async () => {
    assertError(await call('GET', '/api/v1/garments', { key: null }), 401, 'UNAUTHENTICATED');
  });

  test('a bad key is 401', async () => {
    assertError(await call('GET', '/api/v1/garments', { key: 'fb_not_a_key' }), 401, 'UNAUTHENTICATED');
  });

  test('a malformed JSON body is 400', async () => {
    const answer = await call('POST', '/api/v1/fit', { body: '{"weights": ', contentType: 'application/json' });
    assertError(answer, 400, 'INVALID_ARGUMENT');
  });

  test('a bad OBJ is 400', async () => {
    const { population } = await garment();
    const answer = await call('POST', `/api/v1/bodies/project?population=${encodeURIComponent(population)}`, {
      body: BAD_OBJ,
      contentType: 'text/plain',
    });
    assertError(answer, 400, 'INVALID_ARGUMENT');
  });

  test('an unknown garment is 404', async () => {
    const { population } = await garment();
    const body = await call('POST', '/api/v1/bodies/from-measurements', {
      body: JSON.stringify({ population, measurements: { stature_cm: 168, weight_kg: 65 } }),
      contentType: 'application/json',
    });
    assert.equal(body.status, 200, body.text.slice(0, 300));
    const answer = await call('POST', '/api/v1/fit', {
      body: JSON.stringify({ weights: body.json.weights, garment_id: 'no-such-garment' }),
      contentType: 'application/json',
    });
    assertError(answer, 404, 'NOT_FOUND');
    assertError(await call('GET', '/api/v1/garments/no-such-garment/topology'), 404, 'NOT_FOUND');
  });

  test('a scan comes back as itself with body=own, and the garment is fitted to it', async (t) => {
    if (!args.scan) return t.skip('no --scan');
    const { population, garment_id } = await garment();
    const scan = fs.readFileSync(args.scan);
    const project = (body) =>
      call('POST', `/api/v1/bodies/project?population=${encodeURIComponent(population)}${body}`, {
        body: scan,
        contentType: 'text/plain',
      });
    const own = await project('&body=own');
    const ofWeights = await project('');
    assert.equal(own.status, 200, own.text.slice(0, 300));
    assert.equal(ofWeights.status, 200, ofWeights.text.slice(0, 300));
    assert.equal(own.json.body.positions.vertex_count, 13380);
    assert.ok(own.json.body.positions.draco?.data, 'the scan is not Draco-encoded');
    assert.notEqual(own.json.body.positions.draco.data, ofWeights.json.body.positions.draco.data);
    assert.deepEqual(own.json.weights, ofWeights.json.weights);
    const fit = (body) =>
      call('POST', '/api/v1/fit', {
        body: JSON.stringify({ weights: own.json.weights, garment_id, body }),
        contentType: 'application/json',
      });
    const onScan = await fit(own.json.body);
    assert.equal(onScan.status, 200, onScan.text.slice(0, 300));
    const onWeights = await fit(undefined);
    assert.equal(onWeights.status, 200, onWeights.text.slice(0, 300));
    assert.notEqual(
      onScan.json.outfit.garments[0].positions.draco.data,
      onWeights.json.outfit.garments[0].positions.draco.data,
    );
    // Another person's body with these weights is refused.
    const other = await call('POST', '/api/v1/bodies/from-measurements', {
      body: JSON.stringify({ population, measurements: { stature_cm: 150, weight_kg: 95 } }),
      contentType: 'application/json',
    });
    assert.equal(other.status, 200, other.text.slice(0, 300));
    const refused = await fit(other.json.avatar);
    assertError(refused, 400, 'INVALID_ARGUMENT');
    assert.match(refused.json.error.message, /from the body of the weights/);
    assertError(await project('&body=skin'), 400, 'INVALID_ARGUMENT');
  });

  test('a body over 8 MiB is 413', async () => {
    const { population } = await garment();
    const answer = await call('POST', `/api/v1/bodies/project?population=${encodeURIComponent(population)}`, {
      body: oversizedObj(),
      contentType: 'text/plain',
    });
    assertError(answer, 413);
  });

  test('an unknown population is 404', async () => {
    assertError(await call('GET', '/api/v1/bodies/topology?population=no-such-population'), 404, 'NOT_FOUND');
    const answer = await call('POST', '/api/v1/bodies/from-measurements', {
      body: JSON.stringify({ population: 'no-such-population', measurements: { stature_cm: 168, weight_kg: 65 } }),
      contentType: 'application/json',
    });
    assertError(answer, 404, 'NOT_FOUND');
  });

  test('the server still answers /healthz', async () => {
    const answer = await call('GET', '/healthz', { key: null });
    assert.equal(answer.status, 200);
    assert.equal(answer.text.trim(), 'ok');
  });
});

// ---- The page, in Chromium -----------------------------------------------------------------

const CHROMIUM_ARGS = [
  '--headless=new',
  '--no-sandbox',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--disable-gpu-sandbox',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
  '--disable-quic',
];

const settled = (page) =>
  page.waitForFunction(() => document.body.dataset.state !== 'loading', null, { timeout: SETTLE_MS });

// From about:blank, so that a URL differing only in its fragment still loads the page anew.
async function open(page, url) {
  await page.goto('about:blank');
  await page.goto(url);
}

async function state(page) {
  return page.evaluate(() => document.body.dataset.state);
}

async function expectReady(page) {
  await settled(page);
  const now = await state(page);
  if (now !== 'ready') assert.fail(`page state ${now}, error: ${await page.textContent('#error')}`);
  assert.equal(await page.isHidden('#error'), true, 'an error is shown');
}

// Runs action, which makes the page call the API at a URL containing urlPart, and returns
// that response as the page got it (null when the request failed on the network).
async function apiCallOf(page, urlPart, action) {
  let request = null;
  const onRequest = (r) => {
    if (!request && r.url().includes(urlPart)) request = r;
  };
  page.on('request', onRequest);
  try {
    await action();
    await settled(page);
  } finally {
    page.off('request', onRequest);
  }
  assert.ok(request, `the page made no request to ${urlPart}; it shows: ${await page.textContent('#error')}`);
  const response = await request.response();
  return response ? { status: response.status(), json: await response.json() } : null;
}

async function expectErrorShown(page, answer, status) {
  assert.ok(answer, `the request failed on the network; the page shows: ${await page.textContent('#error')}`);
  assert.equal(answer.status, status);
  assert.equal(await state(page), 'error');
  assert.equal(await page.isVisible('#error'), true);
  assert.equal((await page.textContent('#error')).trim(), answer.json.error.message);
}

// sRGB pixels of a page screenshot around (x, y). The browser decodes the PNG, which spares a
// PNG decoder here.
async function screenshotPatch(page, x, y, radius = 1) {
  const clip = { x: Math.round(x) - radius, y: Math.round(y) - radius, width: 2 * radius + 1, height: 2 * radius + 1 };
  const png = await page.screenshot({ clip });
  const rgba = await page.evaluate(async (base64) => {
    const blob = await (await fetch(`data:image/png;base64,${base64}`)).blob();
    const bitmap = await createImageBitmap(blob, { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
    const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
    const context = canvas.getContext('2d');
    context.drawImage(bitmap, 0, 0);
    return Array.from(context.getImageData(0, 0, bitmap.width, bitmap.height).data);
  }, png.toString('base64'));
  const mean = [0, 0, 0];
  for (let i = 0; i < rgba.length; i += 4) for (let c = 0; c < 3; c++) mean[c] += rgba[i + c];
  return mean.map((v) => v / (rgba.length / 4));
}

const hexRgb = (hex) => [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
const toLinear = (c) => ((c /= 255) <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4);
const distance = (a, b) => Math.hypot(...a.map((v, i) => v - b[i]));

async function torsoPoint(page) {
  // Client coordinates equal page coordinates (for the screenshot clip) only unscrolled.
  await page.evaluate(() => window.scrollTo(0, 0));
  const point = await page.evaluate(() => window.fitbaseTest.torsoScreenPoint());
  assert.ok(point, 'no garment on the body, or none of its vertices at chest height in front');
  return point;
}

describe('try-on page', { concurrency: 1 }, () => {
  let context;
  let page;
  let userDataDir;
  let swiftShader = false;
  const browserErrors = [];

  before(async () => {
    userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'fitbase-tryon-'));
    context = await chromium.launchPersistentContext(userDataDir, {
      executablePath: args.chromium,
      args: CHROMIUM_ARGS,
      viewport: { width: 1400, height: 900 },
      deviceScaleFactor: 1,
    });
    page = context.pages()[0] ?? (await context.newPage());
    page.on('pageerror', (e) => browserErrors.push(e.message));
  });

  after(async () => {
    await context?.close();
    fs.rmSync(userDataDir, { recursive: true, force: true });
  });

  test('WebGL renders with SwiftShader', async () => {
    await page.goto('about:blank');
    const renderer = await page.evaluate(() => {
      const gl = document.createElement('canvas').getContext('webgl2') ?? document.createElement('canvas').getContext('webgl');
      if (!gl) return null;
      const info = gl.getExtension('WEBGL_debug_renderer_info');
      return gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER);
    });
    assert.ok(renderer, `${args.chromium} has no WebGL: the page cannot render (check the SwiftShader flags)`);
    assert.match(
      renderer,
      /SwiftShader/,
      `WebGL renderer is "${renderer}", not SwiftShader: pixel checks would depend on this machine's GPU`,
    );
    swiftShader = true;
  });

  test('without a key the page shows the service\'s 401 message', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    const answer = await apiCallOf(page, '/api/v1/garments', () => open(page, `${SERVER}/`));
    await expectErrorShown(page, answer, 401);
  });

  test('a sample body is fitted and the garment shows its fit map on the torso', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    await open(page, `${SERVER}/#key=${encodeURIComponent(KEY)}`);
    await expectReady(page);
    assert.ok((await page.locator('#garment option').count()) > 0, 'no garments listed');
    await page.click('#samples [data-sample="average"]');
    await expectReady(page);

    assert.match(await page.textContent('#recommendation'), /We recommend \S+/);
    assert.ok((await page.locator('#size-buttons button[data-size]:not([disabled])').count()) > 0, 'no size buttons');
    for (const mode of ['stretch', 'ease']) {
      await page.selectOption('#map-mode', mode);
      assert.equal(await page.locator('#legend li').count(), 8, `${mode} legend bands`);
    }

    // The plain cloth colour first: at the chest point the garment must cover the body, so the
    // pixel is no background and its hue is the cloth's rather than the skin's.
    await page.selectOption('#map-mode', 'cloth');
    const point = await torsoPoint(page);
    const cloth = await screenshotPatch(page, point.x, point.y);
    const background = hexRgb(await page.evaluate(() => window.fitbaseTest.background));
    const clothColor = await page.evaluate(() => window.fitbaseTest.clothColor);
    assert.ok(distance(cloth, background) > 40, `background at the chest: ${cloth.map(Math.round)}`);
    const hue = (rgb) => rgb.map((v) => v / (rgb[0] + rgb[1] + rgb[2]));
    assert.ok(
      distance(hue(cloth), hue(hexRgb(clothColor))) < distance(hue(cloth), hue(hexRgb(SKIN))),
      `skin, not cloth, at the chest: ${cloth.map(Math.round)}`,
    );

    // The same point with the stretch map. Light scales each linear channel of the albedo;
    // measured from the cloth render at the same pixel, it predicts each band's rendered colour,
    // and the nearest prediction must be the band the map gives this vertex.
    await page.selectOption('#map-mode', 'stretch');
    const mapped = await torsoPoint(page);
    const pixel = (await screenshotPatch(page, mapped.x, mapped.y)).map(toLinear);
    const clothAlbedo = hexRgb(clothColor).map(toLinear);
    const light = cloth.map(toLinear).map((v, c) => v / clothAlbedo[c]);
    const candidates = [...(await page.evaluate(() => window.fitbaseTest.bandColors('stretch'))), SKIN];
    const predicted = (hex) => hexRgb(hex).map(toLinear).map((v, c) => v * light[c]);
    const nearest = candidates.reduce((a, b) => (distance(pixel, predicted(a)) <= distance(pixel, predicted(b)) ? a : b));
    assert.equal(nearest, mapped.color, `the chest pixel (linear ${pixel.map((v) => v.toFixed(3))}) is nearest to ${nearest}, not the map's ${mapped.color}`);

    if (args.screenshot) {
      fs.mkdirSync(path.dirname(path.resolve(args.screenshot)), { recursive: true });
      await page.screenshot({ path: args.screenshot, fullPage: true });
    }
  });

  test('clicking the garment reads the fit map there', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    const point = await torsoPoint(page);
    await page.mouse.click(point.x, point.y);
    assert.equal(await page.isVisible('#probe'), true);
    assert.match(await page.textContent('#probe'), /^stretch (−?\d+\.\d %|no value) · ease (−?\d+\.\d mm|no value)$/);
  });

  test('another size switches the fit map and the advice without a request', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    const before = await page.evaluate(() => window.fitbaseTest.shown());
    const adviceBefore = await page.textContent('#advice');
    const other = page.locator('#size-buttons button[data-size][aria-pressed="false"]').first();
    assert.ok((await other.count()) > 0, 'the garment has only one size');
    const size = await other.getAttribute('data-size');

    const requests = [];
    const onRequest = (r) => r.url().includes('/api/') && requests.push(r.url());
    page.on('request', onRequest);
    await other.click();
    page.off('request', onRequest);

    const after = await page.evaluate(() => window.fitbaseTest.shown());
    assert.equal(after.size, size);
    assert.notEqual(after.checksum, before.checksum, 'the fit map did not change');
    assert.notEqual(await page.textContent('#advice'), adviceBefore, 'the advice did not change');
    assert.equal(await page.getAttribute(`#size-buttons [data-size="${size}"]`, 'aria-pressed'), 'true');
    assert.deepEqual(requests, []);
  });

  test('typed measurements make a body and fit it', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    await page.fill('#stature', '171.5');
    await page.fill('#weight', '68');
    await page.fill('#waist', '78');
    await page.click('#fit-measurements');
    await expectReady(page);
    assert.match(await page.textContent('#body-note'), /171\.5 cm, 68 kg/);
    assert.match(await page.textContent('#recommendation'), /We recommend \S+/);
    assert.ok(await page.evaluate(() => window.fitbaseTest.torsoScreenPoint()), 'no garment on the body');
  });

  test('an uploaded scan is shown as it is and every size is fitted to it', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    if (!args.scan) return t.skip('no --scan');
    let fitRequest = null;
    const onRequest = (r) => {
      if (r.url().includes('/api/v1/fit')) fitRequest = r;
    };
    page.on('request', onRequest);
    try {
      await page.setInputFiles('#upload', {
        name: path.basename(args.scan),
        mimeType: 'text/plain',
        buffer: fs.readFileSync(args.scan),
      });
      await expectReady(page);
    } finally {
      page.off('request', onRequest);
    }
    assert.ok(fitRequest, 'the page asked for no fit');
    const sent = JSON.parse(fitRequest.postData());
    assert.equal(sent.body?.positions?.vertex_count, 13380, 'the fit request did not carry the scan');
    assert.match(await page.textContent('#body-note'), /Your scan/);
    assert.ok(await page.evaluate(() => window.fitbaseTest.torsoScreenPoint()), 'no garment on the body');
  });

  test('a bad OBJ upload shows the service\'s message', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    const answer = await apiCallOf(page, '/api/v1/bodies/project', () =>
      page.setInputFiles('#upload', { name: 'bad.obj', mimeType: 'text/plain', buffer: Buffer.from(BAD_OBJ) }),
    );
    await expectErrorShown(page, answer, 400);
  });

  test('an upload over 8 MiB shows the 413 message', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    const answer = await apiCallOf(page, '/api/v1/bodies/project', () =>
      page.setInputFiles('#upload', { name: 'huge.obj', mimeType: 'text/plain', buffer: oversizedObj() }),
    );
    await expectErrorShown(page, answer, 413);
  });

  test('the error clears on the next success', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    await page.click('#samples [data-sample="average"]');
    await expectReady(page);
  });

  test('an unknown garment shows the service\'s NOT_FOUND message', async (t) => {
    if (!swiftShader) return t.skip('no SwiftShader WebGL');
    const answer = await apiCallOf(page, '/api/v1/garments/no-such-garment/', () =>
      open(page, `${SERVER}/?garment=no-such-garment#key=${encodeURIComponent(KEY)}`),
    );
    await expectErrorShown(page, answer, 404);
    assert.equal(answer.json.error.code, 'NOT_FOUND');
  });

  test('the page raised no script errors', () => {
    assert.deepEqual(browserErrors, []);
  });
});
