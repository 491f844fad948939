// SPDX-License-Identifier: MIT
// Shared by the browser tests: Debian's Chromium (never a downloaded one)
// headless through playwright-core, WebGL in software (SwiftShader); every
// console error and page error collected; any http(s) request refused and
// recorded (the pages must be self-contained).
import { chromium } from 'playwright-core';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';

export function args() {
  const out = {};
  const a = process.argv.slice(2);
  for (let i = 0; i < a.length; i += 2) out[a[i].replace(/^--/, '')] = a[i + 1];
  return out;
}

export async function openPage(file, { browserPath = '/usr/bin/chromium', width = 1500, height = 950 } = {}) {
  const browser = await chromium.launch({
    executablePath: browserPath,
    headless: true,
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--no-sandbox'],
  });
  const page = await browser.newPage({ viewport: { width, height } });
  const errors = [];
  const network = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.route(/^https?:/, (route) => { network.push(route.request().url()); route.abort(); });
  const t0 = Date.now();
  await page.goto('file://' + path.resolve(file));
  await page.waitForSelector('body[data-ready="1"]', { timeout: 180000 });
  // One frame drawn after the data is in.
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const loadSeconds = (Date.now() - t0) / 1000;
  // Where the time went (ms from navigation start): HTML parsed, data parsed, page built.
  const phases = await page.evaluate(() => {
    const at = (name) => Math.round(performance.getEntriesByName(name)[0]?.startTime ?? -1);
    return { html: Math.round(performance.getEntriesByType('navigation')[0].domInteractive), data: at('plancheck-data'), built: at('plancheck-built') };
  });
  return { browser, page, errors, network, loadSeconds, phases };
}

export function checkClean({ errors, network }) {
  assert.deepEqual(errors, [], 'console errors');
  assert.deepEqual(network, [], 'network requests');
}

export function shotDir(dir) {
  fs.mkdirSync(dir, { recursive: true });
  return (name) => path.join(dir, name);
}

// Pixels of the 3D view that are not the background (the canvas is not blank).
export async function drawnPixels(page) {
  return page.evaluate(() => {
    const px = window.plancheck.view.pixels();
    let n = 0;
    for (let i = 0; i < px.length; i += 4) if (Math.abs(px[i] - 0x1b) + Math.abs(px[i + 1] - 0x1f) + Math.abs(px[i + 2] - 0x27) > 30) ++n;
    return n / (px.length / 4);
  });
}
