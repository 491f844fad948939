// SPDX-License-Identifier: MIT
// The viewer of report.html and sweep.html: reads the page's data and builds
// the page. window.plancheck exposes the page's controls to the browser tests.
import uplotCss from 'uplot/dist/uPlot.min.css';
import { pageData } from './common.js';
import { reportPage } from './report.js';
import { sweepPage } from './sweep.js';
import { installStyle } from './style.js';

function start() {
  installStyle(uplotCss);
  const root = document.createElement('div');
  root.id = 'app';
  document.body.append(root);
  // Marks for the browser tests and benchmarks: data parsed, page built.
  const data = pageData();
  performance.mark('plancheck-data');
  window.plancheck = data.kind === 'sweep' ? sweepPage(data, root) : reportPage(data, root);
  performance.mark('plancheck-built');
  document.body.dataset.ready = '1';
}

start();
