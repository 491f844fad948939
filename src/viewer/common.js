// SPDX-License-Identifier: MIT
// Shared by both pages: reading the page data, base64 arrays, the 3D view
// (three.js renderer, orbit controls, Z up), a render-on-demand loop.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export function pageData() {
  const el = document.getElementById('plancheck-data');
  return JSON.parse(el.textContent);
}

function bytes(b64) {
  const s = atob(b64);
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out;
}
export const f32 = (b64) => new Float32Array(bytes(b64).buffer);
export const f64 = (b64) => new Float64Array(bytes(b64).buffer);
export const u32 = (b64) => new Uint32Array(bytes(b64).buffer);
export const i32 = (b64) => new Int32Array(bytes(b64).buffer);
export const u8 = (b64) => bytes(b64);
export const i8 = (b64) => new Int8Array(bytes(b64).buffer);
// quantized_json (src/output/scene_page.h): 16-bit steps over each component's range; NaN where none.
export function dequantize(qj) {
  const q = new Uint16Array(bytes(qj.q).buffer);
  const k = qj.lo.length;
  const out = new Float32Array(q.length);
  for (let i = 0; i < q.length; ++i) out[i] = q[i] === 65535 ? NaN : qj.lo[i % k] + q[i] * qj.step[i % k];
  return out;
}
// ints_json: int16 or int32.
export const ints = (j) => (j.i16 !== undefined ? new Int16Array(bytes(j.i16).buffer) : i32(j.i32));
// A part's triangle indices (uint16 where its vertices allow).
export const partIndices = (p) => (p.indices16 !== undefined ? new Uint16Array(bytes(p.indices16).buffer) : u32(p.indices));

export function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else if (k === 'text') e.textContent = v;
    else e.setAttribute(k, v);
  }
  for (const c of children) if (c != null) e.append(c);
  return e;
}

export function fmt(v, digits = 4) {
  if (v === null || v === undefined) return '-';
  if (typeof v !== 'number') return String(v);
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a >= 1e5 || a < 1e-3) return v.toExponential(digits - 1);
  return Number(v.toPrecision(digits)).toString();
}

export const VERDICT_COLORS = {
  safe: '#2e7d32', collision: '#c62828', clearance: '#ef8f00', limits: '#6a1b9a', target: '#1565c0',
};
export const VERDICT_BY_CODE = ['safe', 'collision', 'clearance', 'limits', 'target'];

// A 3D view in `container`: renderer, Z-up camera, lights, orbit controls.
// render() draws on the next animation frame (at most once per frame).
export class View3D {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.setClearColor(0x1b1f27);
    container.append(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
    this.camera.up.set(0, 0, 1);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(3, -2, 5);
    this.scene.add(sun);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.render());
    this.pending = false;
    this.beforeRender = [];
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }
  resize() {
    const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }
  // Frames the box (THREE.Box3) from the south-west, above.
  frame(box) {
    const c = box.getCenter(new THREE.Vector3());
    const r = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-3);
    const d = r / Math.sin((this.camera.fov * Math.PI) / 360);
    this.camera.position.copy(c).add(new THREE.Vector3(-0.55, -0.75, 0.45).normalize().multiplyScalar(d * 0.9));
    this.camera.near = d / 1000;
    this.camera.far = d * 20;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(c);
    this.controls.update();
    this.render();
  }
  render() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => this.renderNow());
  }
  renderNow() {
    this.pending = false;
    for (const f of this.beforeRender) f();
    this.renderer.render(this.scene, this.camera);
  }
  // Pixels of the last frame as RGBA bytes (tests and screenshots).
  pixels() {
    this.renderNow();
    const c = this.renderer.domElement;
    const canvas = document.createElement('canvas');
    canvas.width = c.width;
    canvas.height = c.height;
    const ctx = canvas.getContext('2d');
    ctx.drawImage(c, 0, 0);
    return ctx.getImageData(0, 0, c.width, c.height).data;
  }
}

// A height ramp (dark grey-brown to pale) for terrain colours, t in [0, 1].
export function terrainColor(t, out) {
  const a = [0.28, 0.26, 0.24], b = [0.78, 0.76, 0.70];
  const k = Math.min(1, Math.max(0, t));
  out[0] = a[0] + (b[0] - a[0]) * k;
  out[1] = a[1] + (b[1] - a[1]) * k;
  out[2] = a[2] + (b[2] - a[2]) * k;
  return out;
}
