// SPDX-License-Identifier: MIT
export const CSS = `
* { box-sizing: border-box; }
html, body { margin: 0; height: 100%; font: 13px/1.35 system-ui, sans-serif; color: #e8eaed; background: #111418; }
#app { display: grid; height: 100vh; grid-template-columns: 430px 1fr; grid-template-rows: auto 1fr auto; }
header { grid-column: 1 / 3; padding: 6px 12px; background: #1d222b; border-bottom: 1px solid #2c333e; }
header h1 { font-size: 15px; margin: 0; display: inline; }
header .meta { color: #9aa4b2; margin-left: 12px; }
aside { grid-row: 2 / 4; overflow: auto; border-right: 1px solid #2c333e; padding: 8px; }
main { position: relative; min-height: 200px; }
main canvas { display: block; }
#bottom { border-top: 1px solid #2c333e; padding: 6px 10px; background: #171b21; }
h2 { font-size: 13px; margin: 10px 0 4px; color: #b8c2d0; text-transform: uppercase; letter-spacing: .04em; }
table { border-collapse: collapse; width: 100%; }
th, td { padding: 3px 5px; text-align: left; border-bottom: 1px solid #262c36; white-space: nowrap; }
th { color: #9aa4b2; font-weight: 600; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr.plan { cursor: pointer; }
tr.plan:hover { background: #222833; }
tr.plan.selected { background: #29344a; }
.verdict { display: inline-block; padding: 0 6px; border-radius: 8px; color: #fff; font-weight: 600; font-size: 12px; }
a, button.link { color: #8ab4f8; cursor: pointer; background: none; border: none; padding: 0; font: inherit; text-decoration: underline; }
.tree ul { list-style: none; padding-left: 14px; margin: 0; }
.tree > ul { padding-left: 0; }
.tree label { cursor: pointer; }
.tree .static { color: #9aa4b2; }
.timeline { display: flex; align-items: center; gap: 8px; flex-wrap: wrap; }
.timeline input[type=range] { flex: 1; min-width: 200px; }
.timeline button { background: #2a3240; color: #e8eaed; border: 1px solid #3a4352; border-radius: 4px; padding: 2px 8px; cursor: pointer; min-width: 30px; }
.timeline select { background: #2a3240; color: #e8eaed; border: 1px solid #3a4352; }
#stateinfo { margin: 4px 0; color: #c9d1dc; min-height: 2.6em; }
#stateinfo b { color: #fff; }
#stateinfo .params { color: #9aa4b2; }
.label3d { position: absolute; pointer-events: none; background: rgba(0,0,0,.7); color: #fff; padding: 1px 5px; border-radius: 3px; font-size: 12px; white-space: nowrap; transform: translate(-50%, -130%); }
.legend { position: absolute; left: 8px; bottom: 8px; background: rgba(17,20,24,.8); padding: 4px 8px; border-radius: 4px; font-size: 12px; pointer-events: none; }
.legend span { display: inline-block; width: 10px; height: 10px; margin: 0 4px 0 10px; vertical-align: -1px; }
.chart .u-legend { font-size: 12px; }
.chart .u-legend th { color: inherit; }
.hint { color: #7f8a99; font-size: 12px; }
.counts { margin: 2px 0 6px; }
.chip { border: none; border-radius: 8px; color: #fff; font-weight: 600; font-size: 12px; padding: 1px 8px; cursor: pointer; margin: 1px 0; }
#histogram { display: block; margin: 4px 0; }
ul.fault { margin: 2px 0 4px; padding-left: 18px; color: #c9d1dc; }
.filters { margin: 4px 0; }
.filters input, .filters select { background: #2a3240; color: #e8eaed; border: 1px solid #3a4352; }
.plantable { max-height: 45vh; overflow: auto; }
.plantable thead th { position: sticky; top: 0; background: #111418; }
th.sortable { cursor: pointer; text-decoration: underline dotted; }
th.sorted { color: #e8eaed; }
td.name.detail { text-decoration: underline; }
.warning { color: #ff5252; }
.heat { display: flex; gap: 12px; flex-wrap: wrap; align-items: flex-start; }
.heat canvas { image-rendering: pixelated; border: 1px solid #2c333e; cursor: crosshair; }
.sliders label { display: block; margin: 4px 0; }
.sliders input[type=range] { width: 100%; }
select.axis { background: #2a3240; color: #e8eaed; border: 1px solid #3a4352; }
`;

export function installStyle(extra = '') {
  const s = document.createElement('style');
  s.textContent = CSS + extra;
  document.head.append(s);
}
