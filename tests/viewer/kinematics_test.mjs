// SPDX-License-Identifier: MIT
// The page's kinematics (src/viewer/kinematics.js) against the checker's
// transforms carried in report.html, over every plan of the page
// tests/viewer/kinematics_pages.sh writes (ctest viewer.kinematics):
// node kinematics_test.mjs --page DIR/report.html --report DIR/report.json --scene SCENE.json
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { args, openPage, checkClean } from './browser.mjs';

const a = args();
const report = JSON.parse(fs.readFileSync(a.report, 'utf8'));
const opened = await openPage(a.page, { browserPath: a.chromium });
const { page, browser } = opened;
try {
  checkClean(opened);
  const poses = await page.evaluate(() => window.plancheck.poseCheck());
  console.log(`poses of ${report.plans.length} plans at ${poses.states} states: worst ${poses.worst} (tolerance ${poses.tolerance})`);
  assert.ok(poses.states >= report.plans.length, 'every plan compared');
  assert.ok(poses.worst <= poses.tolerance, "the page's poses are the checker's");
  // World objects (the scene's `objects`) are drawn parts: an attached one
  // poses with its parent node, a world one stays put.
  const scene = JSON.parse(fs.readFileSync(a.scene, 'utf8'));
  const objects = scene.objects.map((o) => ({ name: o.name, parent: o.parent }));
  assert.ok(objects.length >= 3 && objects.some((o) => o.parent) && objects.some((o) => !o.parent), 'attached and world objects');
  for (const o of objects) {
    const n = await page.evaluate((name) => window.plancheck.partTriangles(name), o.name);
    assert.ok(n >= 12, `object ${o.name} drawn (${n} triangles)`);
  }
  const identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
  for (const plan of [0, 1, 2, report.plans.length - 1]) {
    const m = await page.evaluate(([p, names]) => {
      const pc = window.plancheck;
      pc.selectPlan(p);
      pc.setState(0);
      return Object.fromEntries(names.map((n) => [n, pc.partMatrix(n)]));
    }, [plan, [...objects.map((o) => o.name), ...objects.filter((o) => o.parent).map((o) => o.parent)]]);
    for (const o of objects) {
      if (o.parent) {
        assert.deepEqual(m[o.name], m[o.parent], `${o.name} moves with ${o.parent} (plan ${plan})`);
        assert.notDeepEqual(m[o.name], identity, `${o.name} posed (plan ${plan})`);
      } else {
        assert.deepEqual(m[o.name], identity, `${o.name} stays in the world (plan ${plan})`);
      }
    }
  }
  // Some plans travel as float64 (angles of many whole turns), others float32.
  const types = await page.evaluate(() => JSON.parse(document.getElementById('plancheck-data').textContent).plans.map((p) => p.params_type));
  assert.ok(types.includes('f64') && types.includes('f32'), `both parameter encodings (${[...new Set(types)]})`);
  checkClean(opened);
  console.log('viewer.kinematics: all checks passed');
} finally {
  await browser.close();
}
