// The per-vertex fit map (SizeFit.ease_mm / stretch_pct) as colours in 8 fixed bands.
//
// The band edges are fixed rather than scaled to each fit, so a colour means the same in every
// size and on every body: a shopper compares sizes by comparing colours.
//   stretch (%):  < −5 | −5..0 | 0..3 | 3..6 | 6..10 | 10..15 | 15..25 | > 25
//     Negative is cloth gathered below its rest shape; up to ~3 % a woven cloth takes
//     unnoticed; past ~10 % it pulls, past 25 % it strains.
//   ease (mm):    < 0 | 0..2 | 2..5 | 5..10 | 10..20 | 20..40 | 40..80 | > 80
//     The fitted garment's distance to the body: below 0 it would cut in, a few mm is
//     skin-close, a few cm is a regular fit, beyond 8 cm the cloth hangs free.
// One diverging scale runs from tight (red) to loose (blue) for both maps, so high stretch
// and low ease share the warm end. A value on an edge falls in the band above it.
import { Color } from 'three';

// ColorBrewer RdYlBu, tight → loose.
const TIGHT_TO_LOOSE = ['#a50026', '#d73027', '#f46d43', '#fdae61', '#fee090', '#abd9e9', '#74add1', '#313695'];

export const MAP_MODES = {
  stretch: {
    field: 'stretch_pct',
    title: 'Stretch',
    unit: '%',
    edges: [-5, 0, 3, 6, 10, 15, 25],
    colors: [...TIGHT_TO_LOOSE].reverse(),
    low: 'gathered',
    high: 'strained',
  },
  ease: {
    field: 'ease_mm',
    title: 'Ease',
    unit: 'mm',
    edges: [0, 2, 5, 10, 20, 40, 80],
    colors: TIGHT_TO_LOOSE,
    low: 'tight',
    high: 'loose',
  },
};

// The garment's colour when no map is shown, and where a map has no value (non-finite).
export const CLOTH_COLOR = '#6b7a99';

function bandIndex(value, edges) {
  let band = 0;
  while (band < edges.length && value >= edges[band]) band++;
  return band;
}

const minus = (s) => s.replace('-', '\u2212');

export function formatNumber(value, digits = 1) {
  // + 0 turns a -0 from rounding (-0.04 → "-0.0") into 0.
  return minus((Number(value.toFixed(digits)) + 0).toFixed(digits));
}

// [{color, label}] for the legend, lowest values first.
export function legendBands(mode) {
  const { edges, colors, unit } = MAP_MODES[mode];
  return colors.map((color, i) => {
    let label;
    if (i === 0) label = `< ${formatNumber(edges[0], 0)}`;
    else if (i === edges.length) label = `> ${formatNumber(edges[i - 1], 0)}`;
    else label = `${formatNumber(edges[i - 1], 0)} to ${formatNumber(edges[i], 0)}`;
    return { color, label: `${label} ${unit}` };
  });
}

// The colour (CSS hex) a vertex with this value gets in this mode ('cloth' included).
export function colorOf(mode, value) {
  const map = MAP_MODES[mode];
  if (!map || !Number.isFinite(value)) return CLOTH_COLOR;
  return map.colors[bandIndex(value, map.edges)];
}

// Vertex colours (linear RGB, as three.js wants them) for values; values is null for 'cloth'.
export function vertexColors(mode, values, vertexCount) {
  const out = new Float32Array(3 * vertexCount);
  const color = new Color();
  const palette = new Map();
  for (let v = 0; v < vertexCount; v++) {
    const hex = colorOf(mode, values ? values[v] : NaN);
    if (!palette.has(hex)) palette.set(hex, color.set(hex).toArray());
    out.set(palette.get(hex), 3 * v);
  }
  return out;
}

export function formatValue(mode, value) {
  const { title, unit } = MAP_MODES[mode];
  const text = Number.isFinite(value) ? `${formatNumber(value)} ${unit}` : 'no value';
  return `${title.toLowerCase()} ${text}`;
}
