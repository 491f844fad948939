// SPDX-License-Identifier: MIT
// report.html of many candidate plans (issue 36) in headless Chromium: the
// overview, the plan table (violations first, sort, filter), plans without
// detail replaying their motion, the page's poses against the checker's,
// and a hostile plan name shown as text (issue 31). ctest viewer.many_plans
// runs it on 200 plans; bench/report_page/many_plans.sh on 2,000 (by hand):
// node many_plans_test.mjs --page DIR/report.html --report DIR/report.json
//   [--hostile NAME] [--shot FILE.png] [--chromium PATH]
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { args, openPage, checkClean, drawnPixels } from './browser.mjs';

const a = args();
const report = JSON.parse(fs.readFileSync(a.report, 'utf8'));
const size = fs.statSync(a.page).size;
const opened = await openPage(a.page, { browserPath: a.chromium });
const { page, browser } = opened;
const plans = report.plans;
console.log(`report.html: ${plans.length} plans, ${(size / 1e6).toFixed(1)} MB, first render after ${opened.loadSeconds.toFixed(1)} s ` +
  `(ms: HTML parsed ${opened.phases.html}, data parsed ${opened.phases.data}, page built ${opened.phases.built})`);
try {
  checkClean(opened);
  const drawn = await drawnPixels(page);
  assert.ok(drawn > 0.05, `the 3D view is drawn (${drawn})`);
  if (a.shot) await page.screenshot({ path: a.shot });

  // The overview: counts per verdict, the histogram's plans, the parts at fault.
  const counts = {};
  for (const p of plans) counts[p.verdict] = (counts[p.verdict] || 0) + 1;
  const ov = await page.evaluate(() => window.plancheck.overview());
  assert.deepEqual(ov.counts, counts);
  const binned = ov.bins.reduce((n, b) => n + Object.values(b).reduce((x, y) => x + y, 0), 0);
  assert.equal(binned, plans.filter((p) => p.min_distance !== null).length, 'every plan with a distance in the histogram');
  for (const [v, n] of Object.entries(counts))
    assert.equal(await page.textContent(`#verdictcounts [data-verdict="${v}"]`), `${n} ${v}`);
  const fault = new Map();
  for (const p of plans) for (const part of p.first_violation?.parts || []) fault.set(part, (fault.get(part) || 0) + 1);
  if (fault.size) {
    const [name, n] = ov.partsAtFault[0];
    assert.equal(n, Math.max(...fault.values()), `${name} most often at fault`);
  }

  // The table: violations first, the page opened on its first row.
  const order = await page.evaluate(() => window.plancheck.tableOrder());
  assert.equal(order.length, plans.length);
  const verdictOf = new Map(plans.map((p) => [p.name, p.verdict]));
  const firstSafe = order.findIndex((n) => verdictOf.get(n) === 'safe');
  assert.notEqual(verdictOf.get(order[0]), 'safe', 'the first row is a violating plan');
  assert.equal(firstSafe, plans.length - (counts.safe || 0), 'every violating plan before the safe ones');
  const opening = await page.evaluate(() => window.plancheck.state());
  assert.equal(opening.planName, order[0], 'the page opens on the first row');
  // Sorting by name (twice: descending), then by verdict again.
  const names = plans.map((p) => p.name).sort((x, y) => (x < y ? -1 : x > y ? 1 : 0));
  await page.click('#plans th[data-sort="name"]');
  assert.deepEqual(await page.evaluate(() => window.plancheck.tableOrder()), names);
  await page.click('#plans th[data-sort="name"]');
  assert.deepEqual(await page.evaluate(() => window.plancheck.tableOrder()), [...names].reverse());
  await page.click('#plans th[data-sort="min"]');
  const mins = (await page.evaluate(() => window.plancheck.tableOrder())).map((n) => plans.find((p) => p.name === n).min_distance ?? Infinity);
  assert.ok(mins.every((v, i) => i === 0 || mins[i - 1] <= v), 'sorted by minimum distance');
  await page.click('#plans th[data-sort="verdict"]');
  assert.deepEqual(await page.evaluate(() => window.plancheck.tableOrder()), order);
  // Filters: by verdict (a count chip), by name.
  await page.click('#verdictcounts [data-verdict="safe"]');
  const safe = await page.evaluate(() => window.plancheck.tableOrder());
  assert.equal(safe.length, counts.safe);
  assert.ok(safe.every((n) => verdictOf.get(n) === 'safe'));
  await page.selectOption('#verdictfilter', '');
  const part = plans[1].name.slice(0, 6);
  await page.fill('#namefilter', part);
  const found = await page.evaluate(() => window.plancheck.tableOrder());
  assert.deepEqual([...found].sort(), plans.filter((p) => p.name.toLowerCase().includes(part.toLowerCase())).map((p) => p.name).sort());
  await page.fill('#namefilter', '');

  // Detail: every violating plan and the closest others (the default rule).
  const detail = new Set(await page.evaluate(() => window.plancheck.detailPlans()));
  for (const p of plans) if (p.verdict !== 'safe') assert.ok(detail.has(p.name), `${p.name} (${p.verdict}) carries detail`);
  assert.ok(detail.size < plans.length, 'some plans carry no detail');

  // A plan without detail replays its motion, its chart and verdicts.
  const bare = plans.find((p) => !detail.has(p.name) && p.min_distance_parts && p.states > 2);
  await page.evaluate((n) => window.plancheck.selectPlanByName(n), bare.name);
  const moving = bare.min_distance_parts.find((n) => n !== 'terrain');
  const m0 = await page.evaluate((n) => window.plancheck.partMatrix(n), moving);
  const m1 = await page.evaluate(([n, s]) => { window.plancheck.setState(s); return window.plancheck.partMatrix(n); }, [moving, bare.states - 1]);
  assert.notDeepEqual(m0, m1, `${moving} moves in ${bare.name}`);
  assert.equal(await page.evaluate(() => window.plancheck.chartPoints()), bare.states);
  assert.match(await page.textContent('#stateinfo'), /motion, verdicts and distances only/);
  // Its closest approach, one click away: the state and its pair named by report.json.
  await page.click(`#plans tr.plan[data-index="${plans.indexOf(bare)}"] td:nth-child(4) button`);
  assert.equal((await page.evaluate(() => window.plancheck.state())).state, bare.min_distance_state);
  assert.match(await page.textContent('#stateinfo'), new RegExp(`${bare.min_distance_parts[0]} / ${bare.min_distance_parts[1]}`));

  // The first violation of a violating plan, one click away.
  const bad = plans.find((p) => p.verdict === 'collision' && !p.first_violation.between);
  if (bad) {
    await page.click(`#plans tr.plan[data-index="${plans.indexOf(bad)}"] .first-violation`);
    const st = await page.evaluate(() => window.plancheck.state());
    assert.equal(st.planName, bad.name);
    assert.equal(st.state, bad.first_violation.state);
    assert.equal(await page.textContent('#stateverdict'), 'collision');
    assert.ok(await page.evaluate(() => window.plancheck.highlightTriangles()) > 0, 'intersecting triangles drawn');
  }

  // The page's poses against the checker's, over every plan.
  const poses = await page.evaluate(() => window.plancheck.poseCheck());
  assert.ok(poses.states >= plans.length, `pose checks at ${poses.states} states`);
  assert.ok(poses.worst <= poses.tolerance, `the page's poses are the checker's (${poses.worst} <= ${poses.tolerance})`);

  // A hostile name: listed as text, nothing it holds became markup.
  if (a.hostile) {
    const i = plans.findIndex((p) => p.name === a.hostile);
    assert.ok(i >= 0, 'report.json has the hostile plan');
    assert.equal(await page.textContent(`#plans tr.plan[data-index="${i}"] td.name`), a.hostile);
    assert.equal(await page.evaluate(() => document.querySelectorAll('img, iframe, body > script:not([id]) ~ script').length), 0);
    assert.equal(await page.evaluate(() => window.injected), undefined, 'no injected script ran');
  }
  checkClean(opened);
  console.log('many plans: all checks passed');
} finally {
  await browser.close();
}
