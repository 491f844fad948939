// SPDX-License-Identifier: MIT
// The page's kinematics (src/viewer/kinematics.js) against the checker's
// transforms carried in report.html, over every plan of the page
// tests/viewer/kinematics_pages.sh writes (ctest viewer.kinematics):
// node kinematics_test.mjs --page DIR/report.html --report DIR/report.json
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
  // Some plans travel as float64 (angles of many whole turns), others float32.
  const types = await page.evaluate(() => JSON.parse(document.getElementById('plancheck-data').textContent).plans.map((p) => p.params_type));
  assert.ok(types.includes('f64') && types.includes('f32'), `both parameter encodings (${[...new Set(types)]})`);
  checkClean(opened);
  console.log('viewer.kinematics: all checks passed');
} finally {
  await browser.close();
}
