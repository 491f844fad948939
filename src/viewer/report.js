// SPDX-License-Identifier: MIT
// report.html: an overview across plans, the plan table (violations first,
// sortable, filterable), the scene in 3D at any state of any plan, the
// timeline, the chart. Plans are posed here from their parameters
// (kinematics.js); the plans with detail also carry closest points,
// contacts, probes and the terrain dug.
import * as THREE from 'three';
import uPlot from 'uplot';
import { View3D, f32, f64, u8, i8, dequantize, ints, partIndices, el, fmt, VERDICT_COLORS, VERDICT_BY_CODE, terrainColor } from './common.js';
import { chainPoses, poseDeviation } from './kinematics.js';
import { overview } from './overview.js';

const COLOR_STATIC = new THREE.Color(0x8d939c);
const COLOR_MOVING = new THREE.Color(0x6f9fd8);
const COLOR_COLLIDING = new THREE.Color(0xe53935);
const COLOR_CLOSE = new THREE.Color(0xffa000);

export function reportPage(data, root) {
  const report = data.report;
  const unit = data.length_unit;
  const margin = data.safety_margin;

  // Layout.
  const header = el('header', {}, el('h1', { text: 'plancheck report' }),
    el('span', { class: 'meta', text: `${report.scene} · safety margin ${fmt(margin)} ${unit} · ${report.plans.length} plans` +
      (report.continuous ? ' · continuous' : '') }));
  const aside = el('aside');
  const main = el('main');
  const bottom = el('div', { id: 'bottom' });
  root.append(header, aside, main, bottom);

  const view = new View3D(main);
  const legend = el('div', { class: 'legend' });
  legend.innerHTML = '<span style="background:#e53935"></span>colliding' +
    '<span style="background:#ffff00"></span>intersecting triangles' +
    `<span style="background:#ffa000"></span>below margin` +
    '<span style="background:#00e5ff"></span>closest points' +
    '<span style="background:#00e676"></span>target';
  main.append(legend);
  const distLabel = el('div', { class: 'label3d' });
  distLabel.style.display = 'none';
  main.append(distLabel);

  // Geometry, once.
  const box = new THREE.Box3();
  // The chain carrying most triangles is the lander's (drawn grey like static
  // parts); the others (the arm) are blue.
  const chainTris = {};
  for (const p of data.parts) chainTris[p.chain] = (chainTris[p.chain] || 0) + p.triangles;
  const bodyChain = Number(Object.entries(chainTris).sort((x, y) => y[1] - x[1])[0]?.[0] ?? -1);
  const parts = data.parts.map((p, i) => {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(f32(p.positions), 3));
    g.setIndex(new THREE.BufferAttribute(partIndices(p), 1));
    g.computeBoundingSphere();
    g.computeBoundingBox();
    box.union(g.boundingBox);
    const base = p.chain >= 0 && p.chain !== bodyChain ? COLOR_MOVING : COLOR_STATIC;
    const m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ color: base, flatShading: true, side: THREE.DoubleSide }));
    m.matrixAutoUpdate = false;
    m.name = p.name;
    view.scene.add(m);
    return { ...p, index: i, mesh: m, base };
  });

  // Terrain.
  let terrain = null;
  if (data.terrain) terrain = makeTerrain(data.terrain, view.scene);

  // Overlays: closest points, contact triangles, target, probes.
  const segGeom = new THREE.BufferGeometry();
  segGeom.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6), 3));
  const segment = new THREE.Line(segGeom, new THREE.LineBasicMaterial({ color: 0x00e5ff, depthTest: false }));
  segment.renderOrder = 10;
  const size = box.getSize(new THREE.Vector3()).length() || 1;
  const dotGeom = new THREE.SphereGeometry(size * 0.004, 12, 8);
  const dotMat = new THREE.MeshBasicMaterial({ color: 0x00e5ff, depthTest: false });
  const dots = [new THREE.Mesh(dotGeom, dotMat), new THREE.Mesh(dotGeom, dotMat)];
  for (const d of dots) d.renderOrder = 10;
  view.scene.add(segment, ...dots);
  const highlight = new THREE.Group();
  view.scene.add(highlight);
  const highlightMat = new THREE.MeshBasicMaterial({ color: 0xffff00, side: THREE.DoubleSide, depthTest: false, transparent: true, opacity: 0.55 });
  const edgeMat = new THREE.LineBasicMaterial({ color: 0xffff00, depthTest: false });
  const targetMark = new THREE.Group();
  {
    const m = new THREE.MeshBasicMaterial({ color: 0x00e676, depthTest: false });
    const s = size * 0.02;
    for (const [x, y, z] of [[1, 0, 0], [0, 1, 0], [0, 0, 1]]) {
      const bar = new THREE.Mesh(new THREE.BoxGeometry(x ? s : s / 12, y ? s : s / 12, z ? s : s / 12), m);
      bar.renderOrder = 11;
      targetMark.add(bar);
    }
    targetMark.visible = false;
    view.scene.add(targetMark);
  }
  const scoopDot = new THREE.Mesh(dotGeom, new THREE.MeshBasicMaterial({ color: 0x00e676, depthTest: false }));
  scoopDot.renderOrder = 11;
  scoopDot.visible = false;
  view.scene.add(scoopDot);
  const probeLines = data.probes.map(() => {
    const l = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xff80ff }));
    view.scene.add(l);
    return l;
  });

  // Per plan, decoded on first use.
  const names = data.checked_part_names;
  const partIndex = new Map(names.map((n, i) => [n, i]));
  const nparams = data.parameter_names.length;
  const plans = data.plans.map((p, i) => ({ ...p, index: i, summary: report.plans[i], decoded: null }));
  const extent = Math.max(1, size);
  let poseWorst = 0, poseStates = 0;
  function decoded(plan) {
    if (!plan.decoded) {
      const d = {
        params: plan.params_type === 'f64' ? f64(plan.params) : f32(plan.params),
        distance: f32(plan.distance),
        verdict: u8(plan.verdict),
        pair: plan.pair ? ints(plan.pair) : null,
        points: plan.points ? dequantize(plan.points) : null,
        probeDistance: plan.probe_distance ? dequantize(plan.probe_distance) : null,
        probeHit: plan.probe_hit ? ints(plan.probe_hit) : null,
        segLower: plan.segment_lower_bound ? f32(plan.segment_lower_bound) : null,
        segBad: plan.segment_violation ? u8(plan.segment_violation) : null,
        dig: plan.dig ? digRects(plan.dig) : [],
        digStart: plan.dig_start ? digRects(plan.dig_start)[0] : null,
        chains: new Array(data.chains * 12).fill(0),
        posed: -1,
        // Without detail: the pairs report.json names (first violation, closest approach).
        known: new Map(),
      };
      const s = plan.summary;
      if (s.min_distance_parts) d.known.set(s.min_distance_state, { parts: s.min_distance_parts, kind: 'closest' });
      if (s.first_violation?.parts) d.known.set(s.first_violation.state, { parts: s.first_violation.parts, kind: s.first_violation.kind });
      // The page's poses against the checker's, where the page carries them.
      const cp = plan.checker_poses;
      const dev = poseDeviation(data, d.params, { states: cp.states, transforms: f32(cp.transforms) });
      poseWorst = Math.max(poseWorst, dev);
      poseStates += cp.states.length;
      d.poseDeviation = dev;
      if (!(dev <= 1e-5 * extent)) console.error(`report.html: ${plan.name}: the page's poses differ from the checker's by ${dev}`);
      plan.decoded = d;
    }
    return plan.decoded;
  }
  const dist = (d, s) => (Number.isNaN(d.distance[s]) ? null : d.distance[s]);
  function posed(d, s) {
    if (d.posed !== s) { chainPoses(data, d.params, s * nparams, d.chains); d.posed = s; }
    return d.chains;
  }

  const state = { plan: -1, s: 0, playing: false, loop: true, speed: 1 };

  // Overview across plans, then the plan table.
  const table = el('table', { id: 'plans' });
  const overviewBox = overview(data, report, {
    onVerdict: (v) => { verdictFilter.value = v; applyFilter(); },
  });
  aside.append(overviewBox.element);

  aside.append(el('h2', { text: 'Plans' }));
  const verdictFilter = el('select', { id: 'verdictfilter', title: 'show plans of this verdict' });
  verdictFilter.append(el('option', { value: '', text: 'all verdicts' }), el('option', { value: 'violating', text: 'violating' }));
  for (const v of VERDICT_BY_CODE) if (report.plans.some((p) => p.verdict === v)) verdictFilter.append(el('option', { value: v, text: v }));
  const nameFilter = el('input', { type: 'search', id: 'namefilter', placeholder: 'filter by name' });
  const shown = el('span', { class: 'hint', id: 'shown' });
  aside.append(el('div', { class: 'filters' }, verdictFilter, ' ', nameFilter, ' ', shown));
  verdictFilter.addEventListener('change', () => applyFilter());
  nameFilter.addEventListener('input', () => applyFilter());

  // Sort keys: violations first, then the closest, then by name.
  const RANK = { collision: 0, clearance: 1, limits: 2, target: 3, safe: 4 };
  const minKey = (p) => (p.summary.min_distance === null ? Infinity : p.summary.min_distance);
  const byName = (a, b) => (a.summary.name < b.summary.name ? -1 : a.summary.name > b.summary.name ? 1 : a.index - b.index);
  const SORTS = {
    verdict: (a, b) => (RANK[a.summary.verdict] - RANK[b.summary.verdict]) || (minKey(a) - minKey(b)) || byName(a, b),
    min: (a, b) => (minKey(a) - minKey(b)) || byName(a, b),
    states: (a, b) => (a.summary.states - b.summary.states) || byName(a, b),
    name: byName,
  };
  const sort = { key: 'verdict', dir: 1 };
  const head = el('tr');
  for (const [key, text] of [['name', 'plan'], ['verdict', 'verdict'], ['states', 'states'], ['min', `min (${unit})`], [null, 'first violation']]) {
    const th = el('th', { text });
    if (key) {
      th.classList.add('sortable');
      th.dataset.sort = key;
      th.title = 'sort by ' + text;
      th.addEventListener('click', () => { sort.dir = sort.key === key ? -sort.dir : 1; sort.key = key; applySort(); });
    }
    head.append(th);
  }
  const tbody = el('tbody');
  table.append(el('thead', {}, head), tbody);
  const rows = plans.map((p, i) => {
    const s = p.summary;
    const fv = s.first_violation;
    const fvCell = el('td');
    if (fv) {
      fvCell.append(el('button', {
        class: 'link first-violation', text: `${fv.kind} @${fv.state}${fv.between ? '→' + (fv.state + 1) : ''}`,
        title: (fv.parts || []).join(' / ') + (fv.action ? fv.action : ''),
        onclick: (e) => { e.stopPropagation(); selectPlan(i); setState(fv.state); },
      }));
    } else fvCell.textContent = '-';
    const minCell = el('td', { class: 'num' });
    if (s.min_distance !== null) {
      minCell.append(el('button', {
        class: 'link min', text: fmt(s.min_distance), title: `state ${s.min_distance_state}: ${(s.min_distance_parts || []).join(' / ')}`,
        onclick: (e) => { e.stopPropagation(); selectPlan(i); setState(s.min_distance_state); },
      }));
    } else minCell.textContent = '-';
    const nameCell = el('td', { class: 'name', text: s.name, title: p.detail ? 'every state in detail' : 'motion, verdicts and distances (no per-state detail)' });
    if (p.detail) nameCell.classList.add('detail');
    const tr = el('tr', { class: 'plan', 'data-index': String(i), onclick: () => selectPlan(i) },
      nameCell,
      el('td', {}, el('span', { class: 'verdict', style: `background:${VERDICT_COLORS[s.verdict]}`, text: s.verdict })),
      el('td', { class: 'num', text: String(s.states) }), minCell, fvCell);
    tr.dataset.plan = s.name;
    return tr;
  });
  function applySort() {
    const order = [...plans].sort((a, b) => sort.dir * SORTS[sort.key](a, b));
    for (const th of head.children) th.classList.toggle('sorted', th.dataset.sort === sort.key);
    tbody.replaceChildren(...order.map((p) => rows[p.index]));
  }
  function applyFilter() {
    const v = verdictFilter.value, q = nameFilter.value.toLowerCase();
    let n = 0;
    plans.forEach((p, i) => {
      const s = p.summary;
      const ok = (!v || (v === 'violating' ? s.verdict !== 'safe' : s.verdict === v)) && (!q || s.name.toLowerCase().includes(q));
      rows[i].style.display = ok ? '' : 'none';
      if (ok) ++n;
    });
    shown.textContent = `${n} of ${plans.length} shown`;
  }
  applySort();
  applyFilter();
  aside.append(el('div', { class: 'plantable' }, table));
  const nDetail = plans.filter((p) => p.detail).length;
  const rule = data.detail_rule;
  aside.append(el('p', { class: 'hint', id: 'detailhint', text: `${nDetail} of ${plans.length} plans carry every state in detail ` +
    `(closest points, contacts${data.probes.length ? ', probes' : ''}${data.terrain && data.scoop ? ', terrain dug' : ''}; names underlined): the violating plans and ` +
    (rule.names.length ? `those named by --html-plans` : `the ${rule.closest} closest to the margin (--html-plans)`) +
    '. Every plan replays its motion, verdicts and distances.' +
    (report.left_out ? ` ${report.left_out.static_triangles} static triangles left out (${report.left_out.reason}).` : '') }));

  // Part tree.
  aside.append(el('h2', { text: 'Parts' }));
  aside.append(partTree(data, parts, bodyChain, terrain, data.probes.length ? probeLines : null, () => view.render()));
  aside.append(el('p', { class: 'hint', text: 'Keys: ←/→ step, Shift+←/→ 10 steps, Home/End, Space play/pause. Drag to orbit, right-drag to pan, wheel to zoom.' }));

  // Timeline.
  const btn = (text, title, f) => el('button', { text, title, onclick: f });
  const slider = el('input', { type: 'range', min: '0', max: '0', value: '0', id: 'slider' });
  slider.addEventListener('input', () => setState(Number(slider.value)));
  const playBtn = btn('play', 'play / pause (Space)', () => setPlaying(!state.playing));
  playBtn.id = 'play';
  const loopBox = el('input', { type: 'checkbox', id: 'loop', checked: '' });
  loopBox.addEventListener('change', () => { state.loop = loopBox.checked; });
  const speedSel = el('select', { id: 'speed', title: 'states per second' });
  for (const v of [1, 5, 10, 30, 100, 300]) speedSel.append(el('option', { value: String(v), text: `${v} states/s` }));
  speedSel.value = '30';
  const stateLabel = el('span', { id: 'statelabel' });
  bottom.append(el('div', { class: 'timeline' },
    btn('|◀', 'first state (Home)', () => setState(0)), btn('◀', 'previous state (←)', () => setState(state.s - 1)),
    playBtn, btn('▶', 'next state (→)', () => setState(state.s + 1)),
    btn('▶|', 'last state (End)', () => setState(current().summary.states - 1)),
    slider, stateLabel, el('label', {}, loopBox, ' loop'), speedSel));
  const info = el('div', { id: 'stateinfo' });
  const chartBox = el('div', { class: 'chart', id: 'chart' });
  bottom.append(info, chartBox);

  let chart = null;
  const current = () => plans[state.plan];

  let selectedRow = null;
  function selectPlan(i) {
    if (i === state.plan) return;
    setPlaying(false);
    state.plan = i;
    selectedRow?.classList.remove('selected');
    selectedRow = rows[i];
    selectedRow.classList.add('selected');
    const p = current();
    slider.max = String(p.summary.states - 1);
    targetMark.visible = !!p.target;
    if (p.target) targetMark.position.set(...p.target);
    buildChart();
    terrain?.reset(decoded(p).digStart);
    state.s = -1;
    setState(0);
  }

  function buildChart() {
    chart?.destroy();
    const p = current();
    const d = decoded(p);
    const n = p.summary.states;
    const xs = Array.from({ length: n }, (_, k) => k);
    const distance = xs.map((k) => dist(d, k));
    const viol = xs.map((k) => (d.verdict[k] !== 0 ? (distance[k] ?? 0) : null));
    const series = [{ label: 'state' },
      { label: `min distance (${unit})`, stroke: '#8ab4f8', width: 1.5, points: { show: false } },
      { label: 'margin', stroke: '#ffa000', dash: [6, 4], width: 1, points: { show: false } },
      { label: 'violation', stroke: '#e53935', width: 0, paths: () => null, points: { show: true, size: 6, fill: '#e53935' } }];
    const cols = [xs, distance, xs.map(() => margin), viol];
    if (d.segLower) {
      const lower = Array.from(d.segLower, (v) => (Number.isNaN(v) ? null : v));
      series.push({ label: 'segment lower bound', stroke: '#80cbc4', width: 1, paths: uPlot.paths.stepped({ align: 1 }), points: { show: false } });
      cols.push(lower);
      // Segments that violate, drawn at their lower bound (the segment starts at the state).
      series.push({ label: 'segment violation', stroke: '#ff6e40', width: 0, paths: () => null, points: { show: true, size: 7, fill: '#ff6e40' } });
      cols.push(lower.map((v, k) => (d.segBad[k] ? (v ?? 0) : null)));
    }
    const width = Math.max(300, chartBox.clientWidth || bottom.clientWidth - 20);
    chart = new uPlot({
      width, height: 170, series,
      scales: { x: { time: false } },
      axes: [{ stroke: '#9aa4b2', grid: { stroke: '#262c36' }, label: 'state' },
        { stroke: '#9aa4b2', grid: { stroke: '#262c36' }, label: unit, size: 60 }],
      cursor: { drag: { x: true, y: false } },
      hooks: {
        draw: [(u) => {
          const x = u.valToPos(state.s, 'x', true);
          const ctx = u.ctx;
          ctx.save();
          ctx.strokeStyle = '#ffffff';
          ctx.lineWidth = 1;
          ctx.beginPath();
          ctx.moveTo(x, u.bbox.top);
          ctx.lineTo(x, u.bbox.top + u.bbox.height);
          ctx.stroke();
          ctx.restore();
        }],
      },
    }, cols, chartBox);
    chart.over.addEventListener('click', () => {
      const idx = chart.cursor.idx;
      if (idx !== null && idx !== undefined) setState(idx);
    });
  }

  const tmp = new THREE.Matrix4();
  function partMatrix(p, chains, out) {
    if (p.chain < 0) return out.identity();
    const o = p.chain * 12;
    const c = chains;
    return out.set(c[o], c[o + 1], c[o + 2], c[o + 3], c[o + 4], c[o + 5], c[o + 6], c[o + 7],
      c[o + 8], c[o + 9], c[o + 10], c[o + 11], 0, 0, 0, 1);
  }

  // The state's closest pair: from the detail, else where report.json names it.
  function statePair(d, s) {
    if (d.pair) return [d.pair[s * 2], d.pair[s * 2 + 1]];
    const k = d.known.get(s);
    if (!k) return [-1, -1];
    return [partIndex.get(k.parts[0]) ?? -1, partIndex.get(k.parts[1]) ?? -1];
  }

  function setState(s) {
    const p = current();
    const n = p.summary.states;
    s = Math.max(0, Math.min(n - 1, Math.round(s)));
    if (s === state.s) return;
    state.s = s;
    slider.value = String(s);
    const d = decoded(p);
    const chains = posed(d, s);
    for (const part of parts) {
      partMatrix(part, chains, part.mesh.matrix);
      part.mesh.matrixWorldNeedsUpdate = true;
      part.mesh.material.color.copy(part.base);
      part.status = 'ok';
    }
    // Below the margin: the state's closest pair (amber); colliding (red).
    const [a, b] = statePair(d, s);
    const ds = dist(d, s);
    const v = VERDICT_BY_CODE[d.verdict[s]];
    if (a >= 0 && ((ds !== null && ds < margin) || v === 'collision' || v === 'clearance')) {
      for (const k of [a, b]) if (parts[k]) { parts[k].mesh.material.color.copy(COLOR_CLOSE); parts[k].status = 'close'; }
    }
    highlight.clear();
    const contacts = (p.contacts && p.contacts[String(s)]) || [];
    for (const c of contacts) {
      c.parts.forEach((k, side) => {
        if (!parts[k]) return;
        parts[k].mesh.material.color.copy(COLOR_COLLIDING);
        parts[k].status = 'collision';
        const tris = [...new Set(c.triangles.map((t) => t[side]))];
        const m = triangleMesh(parts[k], tris, highlightMat);
        // Their edges too: a sliver triangle shows as its outline.
        const edges = new THREE.LineSegments(new THREE.EdgesGeometry(m.geometry, 0), edgeMat);
        edges.matrixAutoUpdate = false;
        edges.matrix.copy(m.matrix);
        edges.renderOrder = 9;
        highlight.add(m, edges);
      });
    }
    // Without detail, a colliding state's pair is red (no triangles carried).
    if (!d.pair && v === 'collision') for (const k of [a, b]) if (parts[k]) { parts[k].mesh.material.color.copy(COLOR_COLLIDING); parts[k].status = 'collision'; }
    // Closest points.
    const showSeg = !!d.points && a >= 0 && ds !== null;
    segment.visible = dots[0].visible = dots[1].visible = showSeg;
    if (showSeg) {
      const pos = segGeom.attributes.position;
      for (let i = 0; i < 6; ++i) pos.array[i] = d.points[s * 6 + i];
      pos.needsUpdate = true;
      segGeom.computeBoundingSphere();
      dots[0].position.set(d.points[s * 6], d.points[s * 6 + 1], d.points[s * 6 + 2]);
      dots[1].position.set(d.points[s * 6 + 3], d.points[s * 6 + 4], d.points[s * 6 + 5]);
    }
    distLabel.style.display = showSeg ? '' : 'none';
    distLabel.textContent = showSeg ? `${fmt(ds)} ${unit}` : '';
    // The scoop's bottom point, posed with its part.
    if (data.scoop && parts[data.scoop.part]) {
      scoopDot.visible = true;
      scoopDot.position.set(...data.scoop.bottom_point).applyMatrix4(parts[data.scoop.part].mesh.matrix);
    }
    // Probes: each ray from its posed origin, as long as the reading.
    const np = data.probes.length;
    data.probes.forEach((pr, k) => {
      const part = parts[pr.part];
      const m = part ? part.mesh.matrix : tmp.identity();
      const reading = d.probeDistance ? [d.probeDistance[s * np + k], d.probeHit[s * np + k]] : [pr.max_range, -1];
      const o = new THREE.Vector3(...pr.origin).applyMatrix4(m);
      const pts = [];
      for (const dir of pr.directions) {
        const w = new THREE.Vector3(...dir).transformDirection(m).multiplyScalar(reading[0]);
        pts.push(o.x, o.y, o.z, o.x + w.x, o.y + w.y, o.z + w.z);
      }
      probeLines[k].geometry.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
      probeLines[k].material.color.set(reading[1] >= 0 ? 0xff4081 : 0xb388ff);
    });
    terrain?.show(d, s);
    updateInfo();
    chart?.redraw(false, false);
    view.render();
  }

  // Markers keep their size on screen (about 1% of the view's height).
  const dotRadius = size * 0.004;
  view.beforeRender.push(() => {
    for (const d of [...dots, scoopDot]) d.scale.setScalar((view.camera.position.distanceTo(d.position) * 0.006) / dotRadius);
    targetMark.scale.setScalar((view.camera.position.distanceTo(targetMark.position) * 0.03) / (size * 0.02));
  });
  view.beforeRender.push(() => {
    if (distLabel.style.display === 'none') return;
    const m = new THREE.Vector3().addVectors(dots[0].position, dots[1].position).multiplyScalar(0.5).project(view.camera);
    const w = main.clientWidth, h = main.clientHeight;
    distLabel.style.left = `${(m.x * 0.5 + 0.5) * w}px`;
    distLabel.style.top = `${(-m.y * 0.5 + 0.5) * h}px`;
  });

  function updateInfo() {
    const p = current(), s = state.s;
    const d = decoded(p);
    const v = VERDICT_BY_CODE[d.verdict[s]];
    const [a, b] = statePair(d, s);
    const ds = dist(d, s);
    info.replaceChildren();
    stateLabel.textContent = `state ${s} / ${p.summary.states - 1}` + (p.times ? ` · t = ${fmt(p.times[s])} s` : '');
    const parts1 = [el('b', { text: `${p.name} state ${s}` }), ' ',
      el('span', { class: 'verdict', style: `background:${VERDICT_COLORS[v]}`, text: v, id: 'stateverdict' }), ' '];
    if (ds !== null) parts1.push(`min distance ${fmt(ds)} ${unit}` + (a >= 0 ? ` (${names[a]} / ${names[b]}) ` : ' '));
    const contacts = p.contacts && p.contacts[String(s)];
    if (contacts) parts1.push(`· colliding: ${contacts.map((c) => c.parts.map((k) => names[k]).join(' / ')).join(', ')} `);
    else if (!p.detail && v === 'collision' && a >= 0) parts1.push(`· colliding: ${names[a]} / ${names[b]} `);
    const lim = p.limit && p.limit[String(s)];
    if (lim) parts1.push(`· outside limits: ${lim} `);
    else if (!p.detail && p.summary.first_violation?.state === s && p.summary.first_violation.action) parts1.push(`· outside limits: ${p.summary.first_violation.action} `);
    if (d.segLower && s < d.segLower.length && !Number.isNaN(d.segLower[s]))
      parts1.push(`· segment to ${s + 1}: ≥ ${fmt(d.segLower[s])} ${unit}${d.segBad[s] ? ' (violation)' : ''} `);
    const np = data.probes.length;
    if (d.probeDistance) parts1.push('· probes: ' + data.probes.map((pr, k) => `${pr.name} ${fmt(d.probeDistance[s * np + k])}` +
      (d.probeHit[s * np + k] >= 0 ? ` (${p.probe_targets[d.probeHit[s * np + k]]})` : '')).join(', '));
    if (!p.detail) parts1.push(el('span', { class: 'hint', text: ' · motion, verdicts and distances only (no closest points, contacts or probes carried for this plan: --html-plans)' }));
    if (!(d.poseDeviation <= 1e-5 * extent)) parts1.push(el('b', { class: 'warning', text: ` · the page's poses differ from the checker's by ${fmt(d.poseDeviation)}` }));
    info.append(el('div', {}, ...parts1));
    info.append(el('div', { class: 'params', text: data.parameter_names.map((nm, k) => `${nm} ${fmt(d.params[s * nparams + k], 6)}`).join('  ') }));
  }

  // Playing: `speed` states per second, looping or stopping at the end.
  let last = 0, acc = 0;
  function tick(t) {
    if (!state.playing) return;
    const dt = last ? (t - last) / 1000 : 0;
    last = t;
    acc += dt * Number(speedSel.value);
    if (acc >= 1) {
      const step = Math.floor(acc);
      acc -= step;
      const n = current().summary.states;
      let s = state.s + step;
      if (s >= n) {
        if (state.loop) s = s % n;
        else { s = n - 1; setPlaying(false); }
      }
      setState(s);
    }
    requestAnimationFrame(tick);
  }
  function setPlaying(on) {
    state.playing = on;
    playBtn.textContent = on ? 'pause' : 'play';
    if (on) { last = 0; acc = 0; requestAnimationFrame(tick); }
  }

  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement && e.target.type !== 'range' && e.target.type !== 'checkbox') return;
    const k = e.shiftKey ? 10 : 1;
    if (e.key === 'ArrowRight') setState(state.s + k);
    else if (e.key === 'ArrowLeft') setState(state.s - k);
    else if (e.key === 'Home') setState(0);
    else if (e.key === 'End') setState(current().summary.states - 1);
    else if (e.key === ' ') setPlaying(!state.playing);
    else return;
    e.preventDefault();
  });
  window.addEventListener('resize', () => { if (chart) chart.setSize({ width: Math.max(300, chartBox.clientWidth), height: 170 }); });

  if (terrain) box.union(terrain.box);
  const focus = new THREE.Box3();
  for (const p of parts) focus.union(p.mesh.geometry.boundingBox);
  view.frame(focus.isEmpty() ? box : focus);
  // Opens on the first plan of the table (violations first).
  if (plans.length) selectPlan(Number(tbody.firstChild.dataset.index));

  // For tests and scripted screenshots.
  return {
    view,
    selectPlan, setState, setPlaying,
    state: () => ({ plan: state.plan, planName: plans[state.plan]?.name, state: state.s, playing: state.playing }),
    partMatrix: (name) => parts.find((p) => p.name === name)?.mesh.matrix.elements.slice(),
    selectPlanByName: (name) => selectPlan(plans.findIndex((p) => p.name === name)),
    tableOrder: () => [...tbody.children].filter((r) => r.style.display !== 'none').map((r) => plans[Number(r.dataset.index)].name),
    overview: () => overviewBox.summary,
    // Every plan decoded: the largest difference between the page's poses and
    // the checker's transforms the page carries, over how many states.
    poseCheck: () => { for (const p of plans) decoded(p); return { worst: poseWorst, states: poseStates, tolerance: 1e-5 * extent }; },
    detailPlans: () => plans.filter((p) => p.detail).map((p) => p.name),
    partStatus: (name) => parts.find((p) => p.name === name)?.status,
    // Triangles of a part drawn in the scene (0: absent or hidden).
    partTriangles: (name) => {
      const p = parts.find((q) => q.name === name);
      return p && p.mesh.visible && p.mesh.parent ? p.mesh.geometry.index.count / 3 : 0;
    },
    partColor: (name) => parts.find((p) => p.name === name)?.mesh.material.color.getHexString(),
    highlightTriangles: () => highlight.children.filter((m) => m.isMesh).reduce((n, m) => n + m.geometry.attributes.position.count / 3, 0),
    chartPoints: () => (chart ? chart.data[1].length : 0),
    chartClick: (idx) => {
      const x = chart.valToPos(idx, 'x');
      const r = chart.over.getBoundingClientRect();
      return { x: r.left + x, y: r.top + r.height / 2 };
    },
    distanceLabel: () => distLabel.textContent,
    // Cameras for screenshots: on the intersecting triangles, on the closest points.
    focusContact: () => {
      const b = new THREE.Box3().setFromObject(highlight);
      if (b.isEmpty()) return;
      view.frame(b.expandByScalar(size * 0.04));
    },
    focusClosest: () => {
      const b = new THREE.Box3().setFromPoints([dots[0].position, dots[1].position]);
      view.frame(b.expandByScalar(size * 0.04));
    },
    redPixels: () => {
      const px = view.pixels();
      let n = 0;
      for (let i = 0; i < px.length; i += 4) if (px[i] > 150 && px[i + 1] < 90 && px[i + 2] < 90) ++n;
      return n;
    },
  };
}

// A plan's dug rectangles (report_html.cpp DigTrack): heights as int8 steps
// from the undisturbed terrain (-128: no data).
function digRects(j) {
  const r = ints(j.rects), step = f32(j.step), dz = i8(j.dz);
  const out = [];
  for (let k = 0, at = 0; k < step.length; ++k) {
    const [state, c0, r0, c1, r1] = r.subarray(k * 5, k * 5 + 5);
    const n = (c1 - c0 + 1) * (r1 - r0 + 1);
    out.push({ state, c0, r0, c1, r1, step: step[k], dz: dz.subarray(at, at + n) });
    at += n;
  }
  return out;
}

// The listed triangles of a part, posed like it (drawn over it).
function triangleMesh(part, tris, material) {
  const pos = part.mesh.geometry.attributes.position.array;
  const idx = part.mesh.geometry.index.array;
  const out = new Float32Array(tris.length * 9);
  tris.forEach((t, k) => {
    for (let v = 0; v < 3; ++v) {
      const i = idx[t * 3 + v];
      out.set(pos.subarray(i * 3, i * 3 + 3), k * 9 + v * 3);
    }
  });
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(out, 3));
  const m = new THREE.Mesh(g, material);
  m.matrixAutoUpdate = false;
  m.matrix.copy(part.mesh.matrix);
  m.renderOrder = 9;
  return m;
}

// The DEM as a surface (vertex colours by height, dug samples darker), and
// the pit as dug through the selected state.
function makeTerrain(t, scene) {
  const { ncols, nrows, cellsize, x0, y0 } = t;
  const base = f32(t.z);
  const z = new Float32Array(base);
  let zmin = Infinity, zmax = -Infinity;
  for (const v of base) if (!Number.isNaN(v)) { zmin = Math.min(zmin, v); zmax = Math.max(zmax, v); }
  const pos = new Float32Array(ncols * nrows * 3);
  const col = new Float32Array(ncols * nrows * 3);
  for (let r = 0; r < nrows; ++r)
    for (let c = 0; c < ncols; ++c) {
      const i = r * ncols + c;
      pos[i * 3] = x0 + c * cellsize;
      pos[i * 3 + 1] = y0 + r * cellsize;
    }
  const index = [];
  for (let r = 0; r + 1 < nrows; ++r)
    for (let c = 0; c + 1 < ncols; ++c) {
      const i = r * ncols + c;
      const q = [i, i + 1, i + ncols, i + ncols + 1];
      if (q.some((k) => Number.isNaN(base[k]))) continue;
      index.push(q[0], q[1], q[3], q[0], q[3], q[2]);
    }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  g.setAttribute('color', new THREE.BufferAttribute(col, 3));
  g.setIndex(index);
  const mesh = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ vertexColors: true, flatShading: true, side: THREE.DoubleSide }));
  mesh.name = 'terrain';
  scene.add(mesh);
  const span = Math.max(zmax - zmin, 1e-9);
  const rgb = [0, 0, 0];
  function update(r0 = 0, r1 = nrows - 1, c0 = 0, c1 = ncols - 1) {
    for (let r = r0; r <= r1; ++r)
      for (let c = c0; c <= c1; ++c) {
        const i = r * ncols + c;
        const v = Number.isNaN(z[i]) ? zmin : z[i];
        pos[i * 3 + 2] = v;
        terrainColor((v - zmin) / span, rgb);
        const dug = base[i] - v;
        if (dug > span * 1e-4) { rgb[0] = 0.85; rgb[1] = 0.45; rgb[2] = 0.15; }
        else if (dug < -span * 1e-4) { rgb[0] = 0.55; rgb[1] = 0.75; rgb[2] = 0.35; }
        col.set(rgb, i * 3);
      }
    g.attributes.position.needsUpdate = true;
    g.attributes.color.needsUpdate = true;
  }
  update();
  g.computeBoundingBox();
  g.computeBoundingSphere();
  let start = null, applied = -1;  // the dig steps applied: those with state <= applied
  function apply(rect) {
    const w = rect.c1 - rect.c0 + 1;
    for (let r = rect.r0; r <= rect.r1; ++r)
      for (let c = rect.c0; c <= rect.c1; ++c) {
        const q = rect.dz[(r - rect.r0) * w + c - rect.c0], i = r * ncols + c;
        z[i] = q === -128 ? NaN : base[i] + q * rect.step;
      }
  }
  return {
    mesh,
    box: g.boundingBox,
    reset(digStart) {
      start = digStart;
      z.set(base);
      if (start) apply(start);
      applied = -1;
      update();
    },
    show(d, s) {
      if (!d.dig.length && !start) return;
      if (s < applied) { z.set(base); if (start) apply(start); applied = -1; update(); }
      let r0 = nrows, r1 = -1, c0 = ncols, c1 = -1;
      for (const step of d.dig) {
        if (step.state <= applied) continue;
        if (step.state > s) break;
        apply(step);
        r0 = Math.min(r0, step.r0); r1 = Math.max(r1, step.r1); c0 = Math.min(c0, step.c0); c1 = Math.max(c1, step.c1);
      }
      applied = s;
      if (r1 >= 0) update(r0, r1, c0, c1);
    },
  };
}

function partTree(data, parts, bodyChain, terrain, probeLines, render) {
  const box = el('div', { class: 'tree', id: 'parttree' });
  const nodes = data.nodes;
  // Parts under each node, for a node's checkbox.
  const under = nodes.map(() => []);
  nodes.forEach((n, i) => {
    if (n.part < 0) return;
    for (let k = i; k >= 0; k = nodes[k].parent) under[k].push(n.part);
  });
  const kids = nodes.map(() => []);
  nodes.forEach((n, i) => { if (n.parent >= 0) kids[n.parent].push(i); });
  function item(i) {
    if (!under[i].length) return null;
    const n = nodes[i];
    const cb = el('input', { type: 'checkbox', checked: '', 'data-node': n.name });
    cb.addEventListener('change', () => {
      for (const k of under[i]) parts[k].mesh.visible = cb.checked;
      cb.parentElement.parentElement.querySelectorAll('input').forEach((x) => { x.checked = cb.checked; });
      render();
    });
    const moving = n.part >= 0 && parts[n.part].chain >= 0 && parts[n.part].chain !== bodyChain;
    const label = el('label', { class: n.part >= 0 && !moving ? 'static' : '' }, cb, ' ' + n.name +
      (n.part >= 0 ? ` (${parts[n.part].triangles.toLocaleString()} tri${moving ? ', arm' : ''})` : ''));
    const li = el('li', {}, label);
    const sub = kids[i].map(item).filter((x) => x);
    if (sub.length) li.append(el('ul', {}, ...sub));
    return li;
  }
  const top = el('ul', {}, item(0));
  const extra = (name, objs) => {
    const cb = el('input', { type: 'checkbox', checked: '' });
    cb.addEventListener('change', () => { for (const o of objs) o.visible = cb.checked; render(); });
    top.append(el('li', {}, el('label', {}, cb, ' ' + name)));
  };
  if (terrain) extra('terrain (DEM)', [terrain.mesh]);
  if (probeLines) extra('probe rays', probeLines);
  box.append(top);
  return box;
}
