// SPDX-License-Identifier: MIT
// sweep.html in headless Chromium (ctest viewer.sweep):
// node sweep_test.mjs --page DIR/sweep.html --sweep DIR/sweep.json --shots DIR
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { args, openPage, checkClean, shotDir, drawnPixels } from './browser.mjs';

const a = args();
const sweep = JSON.parse(fs.readFileSync(a.sweep, 'utf8'));
const shot = shotDir(a.shots);
const opened = await openPage(a.page, { browserPath: a.chromium });
const { page, browser } = opened;
console.log(`sweep.html: ${(fs.statSync(a.page).size / 1e6).toFixed(1)} MB, loaded in ${opened.loadSeconds.toFixed(1)} s`);
try {
  checkClean(opened);
  // Counts per verdict, as page text, equal sweep.json's; so do the counts from the page's grid.
  const shown = await page.$$eval('#counts tr[data-verdict]', (trs) =>
    Object.fromEntries(trs.map((tr) => [tr.dataset.verdict, Number(tr.querySelector('.all').textContent)])));
  const expected = { safe: sweep.counts.safe, clearance: sweep.counts.clearance, collision: sweep.counts.collision, limits: sweep.counts.limits };
  assert.deepEqual(shown, expected);
  assert.deepEqual(await page.evaluate(() => window.plancheck.counts()), expected);
  const total = Object.values(expected).reduce((x, y) => x + y, 0);
  assert.equal(total, sweep.configurations);
  // The closest configuration without contact: its pair, or a certified bound (no pair).
  if (sweep.min_distance) {
    const hint = await page.$$eval('p.hint', (ps) => ps.map((p) => p.textContent).find((t) => t.startsWith('closest without contact')));
    assert.ok(hint, 'the closest configuration without contact is shown');
    if (sweep.min_distance.is_bound) assert.match(hint, /at least .*certified bound/);
    else assert.ok(hint.includes(sweep.min_distance.parts.join(' / ')), hint);
  }

  // Each slice's counts: summed over every value of a third axis (the others
  // fixed) they equal the counts of the sub-grid, computed from sweep.json's axes.
  const axes = sweep.axes;
  assert.ok(axes.length >= 2, 'a sweep over at least two parameters');
  const slice = await page.evaluate(() => window.plancheck.sliceCounts());
  assert.equal(Object.values(slice).reduce((x, y) => x + y, 0), axes[0].values.length * axes[1].values.length);
  // The heat map's cells follow the grid: hovering cell (ix, iy) names the verdict stored there.
  const fixed = axes.map((ax) => Math.floor(ax.values.length / 2));
  for (const [ix, iy] of [[0, 0], [axes[0].values.length - 1, 1], [2, axes[1].values.length - 1]]) {
    const got = await page.evaluate(([x, y]) => window.plancheck.hoverCell(x, y), [ix, iy]);
    const digits = fixed.slice();
    digits[0] = ix;
    digits[1] = iy;
    assert.equal(got.verdict, await page.evaluate((d) => window.plancheck.verdictAt(d), digits));
  }
  // The safe column of the first axis in sweep.json (safe_configurations per value)
  // equals the page's safe counts summed over the slices of the other axes.
  if (axes.length === 2) {
    const perValue = axes[0].safe_configurations;
    assert.equal(perValue.reduce((x, y) => x + y, 0), expected.safe);
  }

  // The arm moves with the configuration under the pointer.
  const arm = await page.evaluate(() => window.plancheck.partMatrix('Scoop'));
  if (arm) {
    await page.evaluate(() => window.plancheck.hoverCell(0, 0));
    const m0 = await page.evaluate(() => window.plancheck.partMatrix('Scoop'));
    await page.evaluate(() => window.plancheck.hoverCell(5, 5));
    const m1 = await page.evaluate(() => window.plancheck.partMatrix('Scoop'));
    assert.notDeepEqual(m0, m1, 'the scoop moves between two cells');
  }
  // Pointing with the mouse works the same way.
  const box = await page.locator('#heat').boundingBox();
  await page.mouse.move(box.x + 3, box.y + box.height - 3);
  assert.match(await page.textContent('#hoverinfo'), /^configuration 0?\d*: /);
  assert.ok(await drawnPixels(page) > 0.05, 'the 3D view is drawn');
  assert.equal(await page.evaluate(() => window.plancheck.safeTargets()) > 0, expected.safe > 0);
  await page.screenshot({ path: shot('sweep.png') });
  checkClean(opened);
  console.log('viewer.sweep: all checks passed');
} finally {
  await browser.close();
}
