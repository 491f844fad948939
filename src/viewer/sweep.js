// SPDX-License-Identifier: MIT
// sweep.html: the verdict grid as a heat map over two chosen parameters (the
// others set by sliders), the arm at the configuration under the pointer,
// the targets of the safe configurations over the terrain seen from above.
import * as THREE from 'three';
import { View3D, f32, partIndices, el, fmt, VERDICT_COLORS } from './common.js';

const CODES = ['safe', 'clearance', 'collision', 'limits'];
const CODE_RGB = [[46, 125, 50], [239, 143, 0], [198, 40, 40], [106, 27, 154]];

export function sweepPage(data, root) {
  const sweep = data.sweep;
  const unit = data.length_unit;
  // The page's cells: every configuration, or when the grid is finer than
  // the page holds, blocks of `stride` values per axis (sweep_html.h).
  const axes = data.axes;
  const pooled = axes.some((a) => a.stride > 1);
  // Configuration numbers in the full grid (the first of a cell's block).
  const fullStrides = axes.map(() => 1);
  for (let k = axes.length - 2; k >= 0; --k) fullStrides[k] = fullStrides[k + 1] * axes[k + 1].values_total;
  const verdicts = (() => { const s = atob(data.verdicts); const v = new Uint8Array(s.length); for (let i = 0; i < s.length; ++i) v[i] = s.charCodeAt(i); return v; })();
  // Strides of the grid (C order, the last axis fastest).
  const strides = axes.map(() => 1);
  for (let k = axes.length - 2; k >= 0; --k) strides[k] = strides[k + 1] * axes[k + 1].count;

  const header = el('header', {}, el('h1', { text: 'plancheck sweep' }),
    el('span', { class: 'meta', text: `${sweep.scene} · ${sweep.configurations.toLocaleString()} configurations over ${axes.map((a) => `${a.name} (${a.values_total})`).join(', ')}` }));
  const aside = el('aside');
  const main = el('main');
  const bottom = el('div', { id: 'bottom' });
  root.append(header, aside, main, bottom);

  // Counts per verdict: the whole grid (page text), and this slice.
  const counts = [0, 0, 0, 0];
  for (const v of verdicts) ++counts[v];
  aside.append(el('h2', { text: 'Verdicts' }));
  const countTable = el('table', { id: 'counts' }, el('tr', {}, el('th', { text: 'verdict' }), el('th', { text: 'all' }), el('th', { text: 'this slice' })));
  const sliceCells = CODES.map((name, c) => {
    const cell = el('td', { class: 'num slice' });
    countTable.append(el('tr', { 'data-verdict': name }, el('td', {}, el('span', { class: 'verdict', style: `background:${VERDICT_COLORS[name]}`, text: name })),
      el('td', { class: 'num all', text: String(sweep.counts[name]) }), cell));
    return cell;
  });
  aside.append(countTable);
  if (pooled) {
    aside.append(el('p', { class: 'hint', id: 'pooled', text: `The grid is finer than the page holds: each cell shows the most severe verdict ` +
      `(collision, limits, clearance, safe) of the ${axes.map((a) => a.stride).join(' × ')} configurations it covers ` +
      `(${axes.filter((a) => a.stride > 1).map((a) => `${a.name} in blocks of ${a.stride} values`).join(', ')}; the arm is posed at the first value of a block). ` +
      `"all" counts every configuration (sweep.json); "this slice" counts cells. verdict.npy holds every configuration.` }));
  }
  // A certified bound (is_bound) names no pair: see docs/sweeps.md.
  if (sweep.min_distance) aside.append(el('p', { class: 'hint', text: sweep.min_distance.is_bound
    ? `closest without contact: at least ${fmt(sweep.min_distance.distance)} ${unit} (a certified bound; distance.npy has each configuration's)`
    : `closest without contact: ${fmt(sweep.min_distance.distance)} ${unit} (${sweep.min_distance.parts.join(' / ')})` }));

  // Axis choice and sliders for the others.
  aside.append(el('h2', { text: 'Slice' }));
  const xSel = el('select', { class: 'axis', id: 'xaxis' }), ySel = el('select', { class: 'axis', id: 'yaxis' });
  axes.forEach((a, k) => { xSel.append(el('option', { value: String(k), text: a.name })); ySel.append(el('option', { value: String(k), text: a.name })); });
  const state = { x: 0, y: Math.min(1, axes.length - 1), fixed: axes.map((a) => Math.floor(a.count / 2)), hover: null };
  xSel.value = String(state.x);
  ySel.value = String(state.y);
  aside.append(el('div', {}, 'horizontal ', xSel, '  vertical ', ySel));
  const sliders = el('div', { class: 'sliders' });
  aside.append(sliders);
  function buildSliders() {
    sliders.innerHTML = '';
    axes.forEach((a, k) => {
      if (k === state.x || k === state.y) return;
      const label = el('span');
      const input = el('input', { type: 'range', min: '0', max: String(a.count - 1), value: String(state.fixed[k]), 'data-axis': a.name });
      const show = () => { label.textContent = `${a.name} = ${fmt(a.values[state.fixed[k]], 6)}`; };
      input.addEventListener('input', () => { state.fixed[k] = Number(input.value); show(); drawHeat(); });
      show();
      sliders.append(el('label', {}, label, input));
    });
  }
  const onAxes = () => {
    state.x = Number(xSel.value);
    state.y = Number(ySel.value);
    buildSliders();
    drawHeat();
  };
  xSel.addEventListener('change', onAxes);
  ySel.addEventListener('change', onAxes);
  aside.append(el('p', { class: 'hint', text: 'Point at a cell to pose the arm there; the right panel shows the targets of all safe configurations from above.' }));

  // Heat map and top view.
  const heat = el('canvas', { id: 'heat', width: '360', height: '360' });
  const top = el('canvas', { id: 'topview', width: '360', height: '360' });
  const hoverInfo = el('div', { id: 'hoverinfo', class: 'hint' });
  bottom.append(el('div', { class: 'heat' }, el('div', {}, el('div', { id: 'heattitle' }), heat), el('div', {}, el('div', { text: 'safe targets from above' }), top)), hoverInfo);
  const heatTitle = bottom.querySelector('#heattitle');

  function index(ix, iy) {
    let i = 0;
    axes.forEach((a, k) => { i += strides[k] * (k === state.x ? ix : k === state.y ? iy : state.fixed[k]); });
    return i;
  }
  function cells() {
    const nx = axes[state.x].count, ny = state.x === state.y ? 1 : axes[state.y].count;
    return { nx, ny };
  }
  function drawHeat() {
    const { nx, ny } = cells();
    const ctx = heat.getContext('2d');
    const slice = [0, 0, 0, 0];
    const w = heat.width, h = heat.height;
    ctx.clearRect(0, 0, w, h);
    // One pixel per cell, then scaled onto the canvas: millions of cells in
    // one image, not one rectangle each.
    const img = new ImageData(nx, ny);
    for (let iy = 0; iy < ny; ++iy)
      for (let ix = 0; ix < nx; ++ix) {
        const v = verdicts[index(ix, state.x === state.y ? ix : iy)];
        ++slice[v];
        // Vertical axis up: iy = 0 at the bottom.
        const o = ((ny - 1 - iy) * nx + ix) * 4;
        img.data[o] = CODE_RGB[v][0];
        img.data[o + 1] = CODE_RGB[v][1];
        img.data[o + 2] = CODE_RGB[v][2];
        img.data[o + 3] = 255;
      }
    const cellsCanvas = document.createElement('canvas');
    cellsCanvas.width = nx;
    cellsCanvas.height = ny;
    cellsCanvas.getContext('2d').putImageData(img, 0, 0);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(cellsCanvas, 0, 0, w, h);
    if (state.hover) {
      ctx.strokeStyle = '#fff';
      ctx.lineWidth = 2;
      ctx.strokeRect((state.hover[0] * w) / nx + 1, ((ny - 1 - state.hover[1]) * h) / ny + 1, w / nx - 2, h / ny - 2);
    }
    sliceCells.forEach((c, k) => { c.textContent = String(slice[k]); });
    const ax = axes[state.x], ay = axes[state.y];
    const range = (a) => `${a.name} (${fmt(a.values[0])} … ${fmt(a.values[a.count - 1])}`;
    heatTitle.textContent = state.x === state.y ? `${range(ax)}, right)` : `${range(ay)}, up) over ${range(ax)}, right)`;
    return slice;
  }
  heat.addEventListener('mousemove', (e) => {
    const { nx, ny } = cells();
    const r = heat.getBoundingClientRect();
    const ix = Math.min(nx - 1, Math.max(0, Math.floor(((e.clientX - r.left) / r.width) * nx)));
    const iy = Math.min(ny - 1, Math.max(0, ny - 1 - Math.floor(((e.clientY - r.top) / r.height) * ny)));
    hoverCell(ix, iy);
  });

  // 3D: parts posed from per-action transforms.
  const view = new View3D(main);
  const box = new THREE.Box3();
  const chainTris = {};
  for (const p of data.parts) chainTris[p.chain] = (chainTris[p.chain] || 0) + p.triangles;
  const bodyChain = Number(Object.entries(chainTris).sort((x, y) => y[1] - x[1])[0]?.[0] ?? -1);
  const parts = data.parts.map((p) => {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(f32(p.positions), 3));
    g.setIndex(new THREE.BufferAttribute(partIndices(p), 1));
    g.computeBoundingBox();
    g.computeBoundingSphere();
    box.union(g.boundingBox);
    const color = p.chain >= 0 && p.chain !== bodyChain ? 0x6f9fd8 : 0x8d939c;
    const m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ color, flatShading: true, side: THREE.DoubleSide }));
    m.matrixAutoUpdate = false;
    view.scene.add(m);
    return { ...p, mesh: m, base: color };
  });
  const actions = data.actions.map((a) => ({ axis: a.axis, t: f32(a.transforms) }));
  const c = new THREE.Vector3(...data.centre_m), u = data.unit_m;
  const chainMatrices = data.chain_actions.map(() => new THREE.Matrix4());
  const tmp = new THREE.Matrix4();
  function pose(digits) {
    data.chain_actions.forEach((chain, ci) => {
      const m = chainMatrices[ci].identity();
      for (const a of chain) {
        const act = actions[a];
        const o = act.axis < 0 ? 0 : digits[act.axis] * 12;
        const t = act.t;
        tmp.set(t[o], t[o + 1], t[o + 2], t[o + 3], t[o + 4], t[o + 5], t[o + 6], t[o + 7], t[o + 8], t[o + 9], t[o + 10], t[o + 11], 0, 0, 0, 1);
        m.multiply(tmp);
      }
      // Metres about the scene origin -> page coordinates.
      const e = m.elements;
      const rc = c.clone().applyMatrix3(new THREE.Matrix3().setFromMatrix4(m));
      const shift = new THREE.Vector3(e[12], e[13], e[14]).add(rc).sub(c).divideScalar(u);
      m.setPosition(shift);
    });
    for (const p of parts) {
      if (p.chain < 0) p.mesh.matrix.identity();
      else p.mesh.matrix.copy(chainMatrices[p.chain]);
      p.mesh.matrixWorldNeedsUpdate = true;
    }
  }
  const verdictNames = CODES;
  function hoverCell(ix, iy) {
    state.hover = [ix, iy];
    const digits = axes.map((a, k) => (k === state.x ? ix : k === state.y ? (state.x === state.y ? ix : iy) : state.fixed[k]));
    const i = index(ix, state.x === state.y ? ix : iy);
    const v = verdictNames[verdicts[i]];
    if (data.arm) {
      pose(digits);
      const col = { safe: null, clearance: 0xffa000, collision: 0xe53935, limits: 0xab47bc }[v];
      for (const p of parts) p.mesh.material.color.set(col !== null && p.chain >= 0 && p.chain !== bodyChain ? col : p.base);
      if (data.scoop) {
        const q = new THREE.Vector3(...data.scoop.bottom_point).applyMatrix4(parts[data.scoop.part].mesh.matrix);
        drawTop(q);
      }
    }
    const config = digits.reduce((n, d, k) => n + d * axes[k].stride * fullStrides[k], 0);
    hoverInfo.textContent = `${pooled ? 'cell from ' : ''}configuration ${config}: ${axes.map((a, k) => `${a.name} ${fmt(a.values[digits[k]], 6)}`).join(', ')} → ${v}`;
    drawHeat();
    view.render();
    return { index: i, verdict: v };
  }

  // Terrain from above with the safe targets.
  let terrainImg = null;
  const tb = new THREE.Box3();
  const targets = f32(data.safe_targets);
  for (let i = 0; i < targets.length; i += 3) tb.expandByPoint(new THREE.Vector3(targets[i], targets[i + 1], targets[i + 2]));
  const t = data.terrain;
  if (t) {
    tb.expandByPoint(new THREE.Vector3(t.x0, t.y0, 0));
    tb.expandByPoint(new THREE.Vector3(t.x0 + (t.ncols - 1) * t.cellsize, t.y0 + (t.nrows - 1) * t.cellsize, 0));
    const z = f32(t.z);
    let lo = Infinity, hi = -Infinity;
    for (const v of z) if (!Number.isNaN(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    const cv = document.createElement('canvas');
    cv.width = t.ncols;
    cv.height = t.nrows;
    const img = cv.getContext('2d').createImageData(t.ncols, t.nrows);
    for (let r = 0; r < t.nrows; ++r)
      for (let cc = 0; cc < t.ncols; ++cc) {
        const v = z[r * t.ncols + cc];
        const g = Number.isNaN(v) ? 0 : 60 + 150 * ((v - lo) / Math.max(hi - lo, 1e-9));
        const o = ((t.nrows - 1 - r) * t.ncols + cc) * 4;
        img.data[o] = img.data[o + 1] = img.data[o + 2] = g;
        img.data[o + 3] = 255;
      }
    cv.getContext('2d').putImageData(img, 0, 0);
    terrainImg = cv;
  }
  if (tb.isEmpty()) tb.expandByPoint(new THREE.Vector3(0, 0, 0));
  const span = Math.max(tb.max.x - tb.min.x, tb.max.y - tb.min.y, 1e-6) * 1.08;
  const cx = (tb.min.x + tb.max.x) / 2, cy = (tb.min.y + tb.max.y) / 2;
  const toTop = (x, y) => [((x - cx) / span + 0.5) * top.width, (0.5 - (y - cy) / span) * top.height];
  // The targets drawn once into their own layer (up to 500,000 points; a
  // pointer move redraws only the marker over it).
  let targetLayer = null;
  function targetsImage() {
    if (targetLayer) return targetLayer;
    targetLayer = document.createElement('canvas');
    targetLayer.width = top.width;
    targetLayer.height = top.height;
    const lctx = targetLayer.getContext('2d');
    const img = lctx.createImageData(top.width, top.height);
    for (let i = 0; i < targets.length; i += 3) {
      const [x, y] = toTop(targets[i], targets[i + 1]);
      for (const [px, py] of [[x - 1, y - 1], [x, y - 1], [x - 1, y], [x, y]]) {
        const ix = Math.floor(px), iy = Math.floor(py);
        if (ix < 0 || iy < 0 || ix >= top.width || iy >= top.height) continue;
        const o = (iy * top.width + ix) * 4;
        img.data[o] = 0; img.data[o + 1] = 230; img.data[o + 2] = 118; img.data[o + 3] = 140;
      }
    }
    lctx.putImageData(img, 0, 0);
    return targetLayer;
  }
  function drawTop(mark) {
    const ctx = top.getContext('2d');
    ctx.fillStyle = '#1b1f27';
    ctx.fillRect(0, 0, top.width, top.height);
    if (terrainImg) {
      const [x0, y1] = toTop(t.x0 - t.cellsize / 2, t.y0 - t.cellsize / 2);
      const [x1, y0] = toTop(t.x0 + (t.ncols - 0.5) * t.cellsize, t.y0 + (t.nrows - 0.5) * t.cellsize);
      ctx.drawImage(terrainImg, x0, y0, x1 - x0, y1 - y0);
    }
    ctx.drawImage(targetsImage(), 0, 0);
    if (mark) {
      const [x, y] = toTop(mark.x, mark.y);
      ctx.strokeStyle = '#ff40ff';
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.arc(x, y, 6, 0, Math.PI * 2);
      ctx.stroke();
    }
    // Scale bar.
    const len = niceLength(span * 0.3);
    const px = (len / span) * top.width;
    ctx.fillStyle = '#fff';
    ctx.fillRect(10, top.height - 14, px, 3);
    ctx.font = '11px sans-serif';
    ctx.fillText(`${fmt(len)} ${unit}`, 10, top.height - 18);
  }

  buildSliders();
  drawHeat();
  drawTop(null);
  view.frame(box);
  const mid = axes.map((a) => Math.floor(a.count / 2));
  if (axes.length) hoverCell(mid[state.x], mid[state.y]);

  return {
    view,
    counts: () => Object.fromEntries(CODES.map((n, k) => [n, counts[k]])),
    sliceCounts: () => Object.fromEntries(CODES.map((n, k) => [n, Number(sliceCells[k].textContent)])),
    hoverCell,
    setAxes: (x, y) => { xSel.value = String(x); ySel.value = String(y); onAxes(); },
    setFixed: (k, v) => { state.fixed[k] = v; buildSliders(); return drawHeat(); },
    verdictAt: (digits) => CODES[verdicts[digits.reduce((s, d, k) => s + d * strides[k], 0)]],
    partMatrix: (name) => parts.find((p) => p.name === name)?.mesh.matrix.elements.slice(),
    safeTargets: () => targets.length / 3,
  };
}

function niceLength(limit) {
  const p = Math.pow(10, Math.floor(Math.log10(limit)));
  for (const m of [5, 2, 1]) if (m * p <= limit) return m * p;
  return p;
}
