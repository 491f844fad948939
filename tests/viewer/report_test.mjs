// SPDX-License-Identifier: MIT
// report.html of the default dataset in headless Chromium (ctest viewer.report):
// node report_test.mjs --page DIR/report.html --report DIR/report.json --shots DIR
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { args, openPage, checkClean, shotDir, drawnPixels } from './browser.mjs';

const a = args();
const report = JSON.parse(fs.readFileSync(a.report, 'utf8'));
const shot = shotDir(a.shots);
const size = fs.statSync(a.page).size;
const opened = await openPage(a.page, { browserPath: a.chromium });
const { page, browser } = opened;
console.log(`report.html: ${(size / 1e6).toFixed(1)} MB, loaded in ${opened.loadSeconds.toFixed(1)} s`);
try {
  checkClean(opened);
  assert.ok(size < 12.7e6, 'page no larger than before issue 36 (12.7 MB)');

  // Every plan listed as page text, with report.json's verdict and state
  // count; violations first (then by minimum distance), and the page opens
  // on the first row.
  const rows = await page.$$eval('#plans tr.plan', (trs) => trs.map((tr) => ({
    name: tr.querySelector('.name').textContent,
    verdict: tr.querySelector('.verdict').textContent,
    states: Number(tr.children[2].textContent),
  })));
  const byName = (x, y) => (x.name < y.name ? -1 : x.name > y.name ? 1 : 0);
  assert.deepEqual([...rows].sort(byName), report.plans.map((p) => ({ name: p.name, verdict: p.verdict, states: p.states })).sort(byName));
  const firstSafe = rows.findIndex((r) => r.verdict === 'safe');
  assert.ok(firstSafe > 0, 'a violating plan first');
  assert.ok(rows.slice(firstSafe).every((r) => r.verdict === 'safe'), 'violations before every safe plan');
  assert.equal((await page.evaluate(() => window.plancheck.state())).planName, rows[0].name, 'opens on the first row');
  // The overview: counts per verdict as report.json's; the histogram drawn.
  const counts = {};
  for (const p of report.plans) counts[p.verdict] = (counts[p.verdict] || 0) + 1;
  assert.deepEqual(await page.evaluate(() => window.plancheck.overview().counts), counts);
  // Ten plans: every one carries detail (the default --html-plans).
  assert.equal((await page.evaluate(() => window.plancheck.detailPlans())).length, report.plans.length);
  // The page poses every plan from its parameters as the checker does.
  const poses = await page.evaluate(() => window.plancheck.poseCheck());
  assert.ok(poses.states >= report.plans.length, `pose checks at ${poses.states} states`);
  assert.ok(poses.worst <= poses.tolerance, `the page's poses are the checker's (${poses.worst} <= ${poses.tolerance})`);
  const row = (name) => `#plans tr.plan[data-index="${report.plans.findIndex((p) => p.name === name)}"]`;
  const drawn = await drawnPixels(page);
  assert.ok(drawn > 0.05, `the 3D view is drawn (${drawn})`);
  await page.screenshot({ path: shot('report-start.png') });

  // A moving part moves between states.
  await page.evaluate(() => {
    const pc = window.plancheck;
    pc.selectPlan(0);
    pc.setState(0);
  });
  const p0 = report.plans[0];
  const movingPart = p0.min_distance_parts ? p0.min_distance_parts[0] : null;
  if (movingPart && p0.states > 1) {
    const m0 = await page.evaluate((n) => window.plancheck.partMatrix(n), movingPart);
    const m1 = await page.evaluate(([n, s]) => { window.plancheck.setState(s); return window.plancheck.partMatrix(n); },
      [movingPart, p0.states - 1]);
    assert.notDeepEqual(m0, m1, `${movingPart} moves between state 0 and ${p0.states - 1}`);
  }

  // The first collision, one click away: parts red, triangles highlighted, red pixels.
  const collided = report.plans.find((p) => p.verdict === 'collision' && p.first_violation && !p.first_violation.between);
  assert.ok(collided, 'the default dataset has a plan that collides');
  const fv = collided.first_violation;
  await page.click(`${row(collided.name)} .first-violation`);
  const st = await page.evaluate(() => window.plancheck.state());
  assert.equal(st.planName, collided.name);
  assert.equal(st.state, fv.state);
  for (const part of fv.parts) {
    if (part === 'terrain') continue;
    assert.equal(await page.evaluate((n) => window.plancheck.partStatus(n), part), 'collision', `${part} marked colliding`);
  }
  assert.ok(await page.evaluate(() => window.plancheck.highlightTriangles()) > 0, 'intersecting triangles drawn');
  assert.equal(await page.textContent('#stateverdict'), 'collision');
  const contact = collided.collisions.find((c) => c.state === fv.state);
  assert.ok(contact, 'report lists the colliding state');
  const red = await page.evaluate(() => window.plancheck.redPixels());
  assert.ok(red > 200, `red pixels at the collision (${red})`);
  await page.evaluate(() => window.plancheck.focusContact());
  await page.screenshot({ path: shot(`${collided.name}-collision-state${fv.state}.png`) });
  // The state before the first violation is not drawn colliding.
  if (fv.state > 0) {
    await page.keyboard.press('ArrowLeft');
    const before = await page.evaluate(() => window.plancheck.state());
    assert.equal(before.state, fv.state - 1, 'ArrowLeft steps back');
    for (const part of fv.parts)
      if (part !== 'terrain') assert.notEqual(await page.evaluate((n) => window.plancheck.partStatus(n), part), 'collision');
    await page.keyboard.press('ArrowRight');
    assert.equal((await page.evaluate(() => window.plancheck.state())).state, fv.state, 'ArrowRight steps on');
  }

  // The chart: one point per state; a click moves the timeline there.
  assert.equal(await page.evaluate(() => window.plancheck.chartPoints()), collided.states);
  const target = Math.floor(collided.states / 3);
  const xy = await page.evaluate((i) => window.plancheck.chartClick(i), target);
  await page.mouse.move(xy.x, xy.y);
  await page.mouse.click(xy.x, xy.y);
  assert.equal((await page.evaluate(() => window.plancheck.state())).state, target, 'chart click moves the timeline');
  assert.equal(Number(await page.inputValue('#slider')), target, 'the slider follows');

  // The closest approach of a safe plan (plan07 in the default dataset): the segment and its distance.
  const close = report.plans.find((p) => p.name === 'plan07') || report.plans.find((p) => p.min_distance !== null);
  await page.click(`${row(close.name)} td:nth-child(4) button`);
  const cs = await page.evaluate(() => window.plancheck.state());
  assert.equal(cs.planName, close.name);
  assert.equal(cs.state, close.min_distance_state);
  const label = await page.evaluate(() => window.plancheck.distanceLabel());
  assert.ok(label.startsWith(String(Number(close.min_distance.toPrecision(4)))), `distance label ${label} for ${close.min_distance}`);
  await page.evaluate(() => window.plancheck.focusClosest());
  await page.screenshot({ path: shot(`${close.name}-closest-state${close.min_distance_state}.png`) });

  // Playing advances the state.
  await page.click('#play');
  await page.waitForTimeout(700);
  await page.click('#play');
  const played = await page.evaluate(() => window.plancheck.state());
  assert.ok(played.state !== close.min_distance_state, 'play moves the timeline');
  checkClean(opened);
  console.log('viewer.report: all checks passed');
} finally {
  await browser.close();
}
