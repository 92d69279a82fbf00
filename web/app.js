// The shopper's try-on page: pick a garment and a body, see every size on the body with its
// fit map, and the size advice. API contract: docs/http-api.md.
import { createApi } from './lib/api.js';
import { buildGeometry, decodePositions, triangulate } from './lib/mesh.js';
import { CLOTH_COLOR, MAP_MODES, colorOf, formatNumber, formatValue, legendBands, vertexColors } from './lib/fitmap.js';
import { BACKGROUND, Viewer } from './lib/viewer.js';

const $ = (id) => document.getElementById(id);

// Typical adult bodies (stature cm, weight kg) for shoppers who have no scan and would rather
// not type their own. Keyed by the garment's population; the same ids across populations.
const SAMPLES = {
  women: [
    { id: 'petite', label: 'Petite', stature_cm: 158, weight_kg: 52 },
    { id: 'average', label: 'Average', stature_cm: 168, weight_kg: 65 },
    { id: 'tall', label: 'Tall', stature_cm: 180, weight_kg: 75 },
  ],
  men: [
    { id: 'slim', label: 'Slim', stature_cm: 170, weight_kg: 65 },
    { id: 'average', label: 'Average', stature_cm: 178, weight_kg: 80 },
    { id: 'tall', label: 'Tall', stature_cm: 190, weight_kg: 95 },
  ],
};

const REGION_NAMES = {
  bust: 'Bust',
  waist: 'Waist',
  hip: 'Hip',
  thigh: 'Thigh',
  upper_arm: 'Upper arm',
  garment_length: 'Length',
  sleeve_length: 'Sleeve length',
};

// Chest height as a share of stature on an adult body, for the tests' probe point.
const CHEST_HEIGHT = 0.72;

let apiKey = keyFromHash();
const api = createApi(() => apiKey);
const viewer = new Viewer($('canvas'), { onPick: pickVertex });

const state = {
  garments: [], // GarmentSummary[] of the tenant
  garment: null, // the GarmentSummary shown
  topology: null, // { triangles, wireOrder } of that garment
  body: null, // { population, weights, own: the scan as an Avatar or null, label, warnings }
  fit: null, // { advice, sizes: [{ size, geometry, sizeFit, values: { ease, stretch } }] }
  size: null,
  mode: $('map-mode').value,
  probeVertex: null,
};

// Topologies travel once per garment and per population; a failed load is retried next time.
const garmentTopologies = new Map();
const bodyTopologies = new Map();

function cached(cache, key, load) {
  if (!cache.has(key)) {
    const pending = load();
    pending.catch(() => cache.delete(key));
    cache.set(key, pending);
  }
  return cache.get(key);
}

const garmentTopology = (id) =>
  cached(garmentTopologies, id, () =>
    api.garmentTopology(id).then((t) => ({ triangles: triangulate(t.faces), wireOrder: t.wire_order ?? [] })),
  );

const bodyTriangles = (population) =>
  cached(bodyTopologies, population, () => api.bodyTopology(population).then((t) => triangulate(t.faces)));

function keyFromHash() {
  return new URLSearchParams(location.hash.slice(1)).get('key') ?? '';
}

// One user action at a time: a newer one makes an older one stale, and a stale action drops
// its results instead of overwriting the newer ones. body[data-state] is what tests wait on.
let generation = 0;

function run(task) {
  const mine = ++generation;
  const stale = () => mine !== generation;
  document.body.dataset.state = 'loading';
  return task(stale).then(
    () => {
      if (stale()) return;
      showError(null);
      document.body.dataset.state = 'ready';
    },
    (error) => {
      if (stale()) return;
      // Not the service's message but a broken answer or a bug here: keep its stack.
      if (!error.code) console.error(error);
      showError(error);
      document.body.dataset.state = 'error';
    },
  );
}

function showError(error) {
  const box = $('error');
  box.textContent = error ? error.message : '';
  box.hidden = !error;
}

// ---- Garments --------------------------------------------------------------------------

async function loadGarments(stale) {
  const { garments = [] } = await api.listGarments();
  if (stale()) return;
  state.garments = garments;
  const select = $('garment');
  select.replaceChildren(...garments.map((g) => new Option(g.name || g.garment_id, g.garment_id)));
  // Blank until a garment has loaded, so that picking any one after a failure is a change.
  select.selectedIndex = -1;
  if (!garments.length) {
    $('stage-note').textContent = 'This shop has no garments to try on yet.';
    return;
  }
  // A product page can link here with its garment: /?garment=ID#key=...
  const wanted = new URLSearchParams(location.search).get('garment');
  await showGarment(wanted || garments[0].garment_id, stale);
}

async function showGarment(id, stale) {
  // The topology first, also for an id the list lacks: the service says what is wrong with it.
  const topology = await garmentTopology(id);
  if (stale()) return;
  const garment = state.garments.find((g) => g.garment_id === id);
  if (!garment) throw new Error('This garment cannot be tried on yet.');
  $('garment').value = id;
  dropFit();
  state.garment = garment;
  state.topology = topology;
  renderSamples();
  renderSizeButtons();
  if (state.body && state.body.population !== garment.population) dropBody();
  if (state.body) await fitBody(stale);
}

// ---- Bodies ----------------------------------------------------------------------------

function renderSamples() {
  const samples = SAMPLES[state.garment.population] ?? [];
  $('samples').replaceChildren(
    ...samples.map((s) => {
      const button = document.createElement('button');
      button.type = 'button';
      button.dataset.sample = s.id;
      button.innerHTML = `<strong></strong><span></span>`;
      button.firstChild.textContent = s.label;
      button.lastChild.textContent = `${s.stature_cm} cm · ${s.weight_kg} kg`;
      button.addEventListener('click', () =>
        run((stale) =>
          fromMeasurements(
            `Sample body: ${s.label.toLowerCase()}, ${s.stature_cm} cm, ${s.weight_kg} kg`,
            { stature_cm: s.stature_cm, weight_kg: s.weight_kg },
            stale,
          ),
        ),
      );
      return button;
    }),
  );
}

// measurements: TypedMeasurements (cm, kg).
function fromMeasurements(label, measurements, stale) {
  return loadBody(
    label,
    (population) =>
      api.bodyFromMeasurements(population, measurements).then((r) => ({ ...r, body: r.avatar })),
    stale,
  );
}

// A scan is shown as it is, and every garment is fitted to it (not to the body of its weights).
function uploadBody(file, stale) {
  const isFba = /\.fba$/i.test(file.name);
  return loadBody(`Your scan: ${file.name}`, (population) => api.projectBody(population, file, isFba), stale, true);
}

// request(population) answers { weights, body: Avatar, out_of_distribution, reasons }. own: the
// body is the shopper's own mesh, sent with every fit.
async function loadBody(label, request, stale, own = false) {
  if (!state.garment) throw new Error('Choose a garment first.');
  const population = state.garment.population;
  const [answer, triangles] = await Promise.all([request(population), bodyTriangles(population)]);
  const positions = await decodePositions(answer.body?.positions);
  if (stale()) return;
  dropFit();
  viewer.setBody(buildGeometry(positions, triangles));
  state.body = {
    population,
    weights: answer.weights,
    own: own ? answer.body : null,
    label,
    warnings: answer.out_of_distribution ? (answer.reasons ?? []) : [],
  };
  $('body-note').textContent = label;
  $('stage-note').hidden = true;
  await fitBody(stale);
}

function dropBody() {
  state.body = null;
  viewer.clearBody();
  $('body-note').textContent = '';
  $('stage-note').textContent = 'Choose a body on the right to try the garment on.';
  $('stage-note').hidden = false;
}

// ---- Fit -------------------------------------------------------------------------------

async function fitBody(stale) {
  const { garment, topology, body } = state;
  const answer = await api.fit(body.weights, garment.garment_id, body.own);
  const advice = answer.advice ?? {};
  const sizeFits = advice.sizes ?? [];
  const sizes = await Promise.all(
    (answer.outfit?.garments ?? []).map(async (fitted) => {
      const positions = await decodePositions(fitted.positions, topology.wireOrder);
      const sizeFit = sizeFits.find((s) => s.size === fitted.size) ?? { size: fitted.size };
      const count = positions.length / 3;
      return {
        size: fitted.size,
        geometry: buildGeometry(positions, topology.triangles),
        sizeFit,
        values: { ease: mapValues(sizeFit, 'ease', count), stretch: mapValues(sizeFit, 'stretch', count) },
      };
    }),
  );
  if (stale()) return;
  // Grading order (smallest first) is the advice's; a size it does not cover goes last.
  const rank = (size) => {
    const i = sizeFits.findIndex((s) => s.size === size);
    return i < 0 ? sizeFits.length : i;
  };
  sizes.sort((a, b) => rank(a.size) - rank(b.size));
  dropFit();
  state.fit = { advice, sizes };
  const recommended = sizes.find((s) => s.size === advice.recommended_size);
  showSize((recommended ?? sizes[0])?.size);
}

// Float32Array of one fit-map field in vertex order, or null when the size has none.
function mapValues(sizeFit, mode, count) {
  const values = sizeFit[MAP_MODES[mode].field] ?? [];
  if (!values.length) return null;
  if (values.length !== count) {
    throw new Error(`The ${mode} map of size ${sizeFit.size} has ${values.length} values for ${count} vertices.`);
  }
  // Number() also reads the JSON mapping's "NaN"/"Infinity" strings.
  return Float32Array.from(values, Number);
}

function dropFit() {
  for (const entry of state.fit?.sizes ?? []) entry.geometry.dispose();
  state.fit = null;
  state.size = null;
  state.probeVertex = null;
  viewer.clearGarment();
  $('probe').hidden = true;
  renderSizeButtons();
  renderAdvice();
}

const shownEntry = () => state.fit?.sizes.find((s) => s.size === state.size) ?? null;
const shownValues = (entry) => (state.mode === 'cloth' ? null : entry.values[state.mode]);

function showSize(size) {
  const entry = state.fit?.sizes.find((s) => s.size === size);
  if (!entry) return;
  state.size = size;
  viewer.setGarment(entry.geometry, colorsOf(entry));
  renderSizeButtons();
  renderAdvice();
  renderProbe();
}

function colorsOf(entry) {
  return vertexColors(state.mode, shownValues(entry), entry.geometry.getAttribute('position').count);
}

function setMode(mode) {
  state.mode = mode;
  renderLegend();
  const entry = shownEntry();
  if (entry) viewer.setGarmentColors(colorsOf(entry));
}

function pickVertex(vertex) {
  state.probeVertex = vertex;
  renderProbe();
}

function renderProbe() {
  const entry = shownEntry();
  const v = state.probeVertex;
  const probe = $('probe');
  if (!entry || v === null) {
    probe.hidden = true;
    viewer.hideMarker();
    viewer.render();
    return;
  }
  const value = (mode) => formatValue(mode, entry.values[mode]?.[v] ?? NaN);
  probe.textContent = `${value('stretch')} · ${value('ease')}`;
  probe.hidden = false;
  viewer.showMarker(v);
}

// ---- Panels ----------------------------------------------------------------------------

function renderSizeButtons() {
  const advice = state.fit?.advice;
  const sizes = state.fit ? state.fit.sizes.map((s) => s.size) : (state.garment?.sizes ?? []);
  $('size-buttons').replaceChildren(
    ...sizes.map((size) => {
      const button = document.createElement('button');
      button.type = 'button';
      button.dataset.size = size;
      button.textContent = size;
      // Sizes show before a fit so the shopper sees what there is, but only a fit fills them.
      button.disabled = !state.fit;
      button.setAttribute('aria-pressed', String(size === state.size));
      if (advice && size === advice.recommended_size) {
        button.classList.add('recommended');
        button.title = 'Our recommendation';
      }
      button.addEventListener('click', () => showSize(size));
      return button;
    }),
  );
}

function renderAdvice() {
  const advice = state.fit?.advice;
  const recommendation = $('recommendation');
  if (!advice) {
    recommendation.textContent = state.body ? '' : 'Choose a body to get a size recommendation.';
  } else if (advice.recommended_size) {
    recommendation.innerHTML = 'We recommend <strong></strong> <span class="confidence"></span>';
    recommendation.querySelector('strong').textContent = advice.recommended_size;
    recommendation.querySelector('.confidence').textContent = `${Math.round((advice.confidence ?? 0) * 100)} % confidence`;
  } else {
    recommendation.textContent = 'We have no size to recommend for this body.';
  }

  const warnings = [...(state.body?.warnings ?? []), ...(advice?.ood_reasons ?? [])];
  const ood = $('ood');
  ood.hidden = !(advice?.out_of_distribution || warnings.length);
  ood.replaceChildren();
  if (!ood.hidden) {
    const title = document.createElement('strong');
    title.textContent = 'Less certain for this body:';
    ood.append(title, list(warnings.length ? warnings : ['it lies outside the bodies this garment was fitted on.']));
  }

  $('reasons').replaceChildren(...listItems(advice?.reasons ?? []));

  $('summaries').replaceChildren(
    ...(advice?.sizes ?? []).map((s) => {
      const item = document.createElement('li');
      item.textContent = s.summary || `${s.size}: ${s.verdict}`;
      item.dataset.size = s.size;
      item.dataset.verdict = s.verdict ?? '';
      item.classList.toggle('current', s.size === state.size);
      return item;
    }),
  );

  renderRegions(shownEntry()?.sizeFit);
}

function renderRegions(sizeFit) {
  const table = $('regions');
  const regions = sizeFit?.regions ?? [];
  table.hidden = !regions.length;
  table.querySelector('caption').textContent = sizeFit ? `Size ${sizeFit.size} on this body` : '';
  table.tBodies[0].replaceChildren(
    ...regions.map((r) => {
      const row = document.createElement('tr');
      const ease = r.ease_cm ?? 0;
      const cells = [
        REGION_NAMES[r.region] ?? r.region,
        `${ease > 0 ? '+' : ''}${formatNumber(ease)} cm`,
        `${formatNumber(r.stretch_pct ?? 0)} %`,
      ];
      for (const text of cells) row.insertCell().textContent = text;
      const verdict = document.createElement('span');
      verdict.className = `verdict verdict-${r.verdict}`;
      verdict.textContent = r.verdict ?? '';
      row.insertCell().append(verdict);
      return row;
    }),
  );
}

function renderLegend() {
  const legend = $('legend');
  if (state.mode === 'cloth') {
    legend.textContent = 'The garment in its own colour, without the fit map.';
    return;
  }
  const map = MAP_MODES[state.mode];
  const rows = legendBands(state.mode).map(({ color, label }) => {
    const item = document.createElement('li');
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = color;
    item.append(swatch, label);
    return item;
  });
  const bands = document.createElement('ol');
  bands.append(...rows.reverse());
  const ends = (text) => Object.assign(document.createElement('p'), { className: 'legend-end', textContent: text });
  legend.replaceChildren(ends(`${map.title}: ${map.high}`), bands, ends(map.low));
}

function listItems(texts) {
  return texts.map((text) => Object.assign(document.createElement('li'), { textContent: text }));
}

function list(texts) {
  const ul = document.createElement('ul');
  ul.append(...listItems(texts));
  return ul;
}

// ---- Wiring ----------------------------------------------------------------------------

function restart() {
  // Another key may be another shop: its garments, bases and bodies all differ.
  garmentTopologies.clear();
  bodyTopologies.clear();
  dropBody();
  dropFit();
  state.garment = null;
  state.topology = null;
  $('samples').replaceChildren();
  $('key').value = apiKey;
  document.querySelector('.key-box').open = !apiKey;
  return run(loadGarments);
}

$('garment').addEventListener('change', (e) => run((stale) => showGarment(e.target.value, stale)));

$('measurements').addEventListener('submit', (e) => {
  e.preventDefault();
  const number = (id) => ($(id).value === '' ? undefined : Number($(id).value));
  const m = {
    stature_cm: number('stature'),
    weight_kg: number('weight'),
    bust_girth_cm: number('bust'),
    waist_girth_cm: number('waist'),
    hip_girth_cm: number('hip'),
  };
  const given = Object.fromEntries(Object.entries(m).filter(([, v]) => v !== undefined));
  run((stale) => fromMeasurements(`Your measurements: ${m.stature_cm} cm, ${m.weight_kg} kg`, given, stale));
});

$('upload').addEventListener('change', (e) => {
  const [file] = e.target.files;
  // Cleared so that choosing the same file again (after fixing it) fires again.
  e.target.value = '';
  if (file) run((stale) => uploadBody(file, stale));
});

$('map-mode').addEventListener('change', (e) => setMode(e.target.value));

$('key').addEventListener('change', (e) => {
  apiKey = e.target.value.trim();
  // Kept in the fragment, which browsers never send, so a reload keeps it.
  history.replaceState(null, '', `${location.pathname}${location.search}#key=${encodeURIComponent(apiKey)}`);
  restart();
});

window.addEventListener('hashchange', () => {
  apiKey = keyFromHash();
  restart();
});

// For the browser tests (tests/tryon.test.mjs): what the view shows, as numbers.
window.fitbaseTest = {
  background: BACKGROUND,
  clothColor: CLOTH_COLOR,
  bandColors: (mode) => [...MAP_MODES[mode].colors],
  // The shown garment's front-most vertex at chest height near the body's middle: its page
  // pixel and the colour the map gives it there.
  torsoScreenPoint() {
    const entry = shownEntry();
    if (!entry || !viewer.body) return null;
    const box = viewer.body.geometry.boundingBox;
    const height = box.max.y - box.min.y;
    const chestY = box.min.y + CHEST_HEIGHT * height;
    const midX = (box.min.x + box.max.x) / 2;
    const position = entry.geometry.getAttribute('position');
    let best = -1;
    for (let v = 0; v < position.count; v++) {
      const near = Math.abs(position.getY(v) - chestY) < 0.02 * height && Math.abs(position.getX(v) - midX) < 0.03 * height;
      if (near && (best < 0 || position.getZ(v) > position.getZ(best))) best = v;
    }
    if (best < 0) return null;
    const values = shownValues(entry);
    return { ...viewer.garmentVertexClientPoint(best), vertex: best, color: colorOf(state.mode, values ? values[best] : NaN) };
  },
  // The shown size and map, with a checksum of its per-vertex values (FNV-1a over the float
  // bits), so a test sees a size switch change the map without reading pixels.
  shown() {
    const entry = shownEntry();
    if (!entry) return null;
    let hash = 0x811c9dc5;
    for (const values of [entry.values.ease, entry.values.stretch]) {
      for (const byte of new Uint8Array(values?.buffer ?? new ArrayBuffer(0))) {
        hash = Math.imul(hash ^ byte, 0x01000193) >>> 0;
      }
    }
    return { size: state.size, mode: state.mode, checksum: hash };
  },
};

renderLegend();
renderAdvice();
restart();
