// SPDX-License-Identifier: MIT
// report.html's overview across plans, from report.json: counts per
// verdict, the distribution of the plans' minimum distances with the
// safety margin marked (bars stacked by verdict), the parts most often at
// fault in a first violation.
import { el, fmt, VERDICT_COLORS } from './common.js';

const ORDER = ['collision', 'clearance', 'limits', 'target', 'safe'];
const BINS = 40;

export function overview(data, report, { onVerdict }) {
  const plans = report.plans;
  const unit = data.length_unit, margin = data.safety_margin;
  const box = el('div', { id: 'overview' });
  box.append(el('h2', { text: 'Overview' }));

  const counts = {};
  for (const p of plans) counts[p.verdict] = (counts[p.verdict] || 0) + 1;
  const chips = el('div', { class: 'counts', id: 'verdictcounts' });
  const violating = plans.length - (counts.safe || 0);
  chips.append(el('span', { text: `${plans.length} plans: ` }));
  for (const v of ORDER) {
    if (!counts[v]) continue;
    chips.append(el('button', { class: 'chip', 'data-verdict': v, style: `background:${VERDICT_COLORS[v]}`,
      title: `show the ${v} plans`, text: `${counts[v]} ${v}`, onclick: () => onVerdict(v) }), ' ');
  }
  if (violating && counts.safe) chips.append(el('button', { class: 'link', text: 'all', onclick: () => onVerdict('') }));
  box.append(chips);

  // The distribution of plan minimum distances.
  const finite = plans.filter((p) => p.min_distance !== null && Number.isFinite(p.min_distance));
  const hi = Math.max(margin * 2, ...finite.map((p) => p.min_distance));
  const width = hi / BINS;
  const bins = Array.from({ length: BINS }, () => Object.fromEntries(ORDER.map((v) => [v, 0])));
  for (const p of finite) bins[Math.min(BINS - 1, Math.floor(p.min_distance / width))][p.verdict] += 1;
  const below = finite.filter((p) => p.min_distance < margin).length;
  const closestSafe = finite.filter((p) => p.verdict === 'safe').sort((a, b) => a.min_distance - b.min_distance)[0];
  const canvas = el('canvas', { id: 'histogram', title: `plans by minimum distance (${unit}), ${BINS} bins of ${fmt(width)}; dashed: the safety margin` });
  box.append(el('div', { class: 'hint' }, `minimum distance per plan (${unit}): ${below} of ${finite.length} below the margin ${fmt(margin)}` +
    (closestSafe ? `; closest safe plan ${closestSafe.name} at ${fmt(closestSafe.min_distance)}` : '')));
  box.append(canvas);
  requestAnimationFrame(() => drawHistogram(canvas, bins, hi, margin));

  // Parts at fault in the first violations.
  const fault = new Map();
  for (const p of plans) for (const part of p.first_violation?.parts || []) fault.set(part, (fault.get(part) || 0) + 1);
  for (const p of plans) if (p.first_violation?.action) fault.set(p.first_violation.action, (fault.get(p.first_violation.action) || 0) + 1);
  const top = [...fault.entries()].sort((a, b) => b[1] - a[1] || (a[0] < b[0] ? -1 : 1)).slice(0, 6);
  if (top.length) {
    box.append(el('div', { class: 'hint', text: 'most often at fault in a first violation:' }));
    box.append(el('ul', { class: 'fault', id: 'faultparts' }, ...top.map(([name, n]) => el('li', { text: `${name} (${n} plans)` }))));
  }
  return { element: box, summary: { counts, bins, binWidth: width, below, partsAtFault: top } };
}

function drawHistogram(canvas, bins, hi, margin) {
  const w = canvas.parentElement ? Math.max(200, canvas.parentElement.clientWidth - 4) : 400, h = 120;
  const dpr = window.devicePixelRatio || 1;
  canvas.width = w * dpr;
  canvas.height = h * dpr;
  canvas.style.width = `${w}px`;
  canvas.style.height = `${h}px`;
  const ctx = canvas.getContext('2d');
  ctx.scale(dpr, dpr);
  const left = 30, bottom = 16, top = 6, plotW = w - left - 6, plotH = h - top - bottom;
  const most = Math.max(1, ...bins.map((b) => ORDER.reduce((n, v) => n + b[v], 0)));
  ctx.fillStyle = '#171b21';
  ctx.fillRect(0, 0, w, h);
  const bw = plotW / bins.length;
  bins.forEach((b, i) => {
    let y = top + plotH;
    for (const v of ORDER) {
      if (!b[v]) continue;
      const bh = (b[v] / most) * plotH;
      ctx.fillStyle = VERDICT_COLORS[v];
      ctx.fillRect(left + i * bw + 0.5, y - bh, Math.max(1, bw - 1), bh);
      y -= bh;
    }
  });
  ctx.strokeStyle = '#9aa4b2';
  ctx.beginPath();
  ctx.moveTo(left, top);
  ctx.lineTo(left, top + plotH);
  ctx.lineTo(left + plotW, top + plotH);
  ctx.stroke();
  const mx = left + (margin / hi) * plotW;
  ctx.strokeStyle = '#ffa000';
  ctx.setLineDash([4, 3]);
  ctx.beginPath();
  ctx.moveTo(mx, top);
  ctx.lineTo(mx, top + plotH);
  ctx.stroke();
  ctx.setLineDash([]);
  ctx.fillStyle = '#9aa4b2';
  ctx.font = '10px system-ui, sans-serif';
  ctx.textAlign = 'right';
  ctx.fillText(String(most), left - 3, top + 8);
  ctx.fillText('0', left - 3, top + plotH);
  ctx.textAlign = 'left';
  ctx.fillText('0', left, h - 3);
  ctx.textAlign = 'right';
  ctx.fillText(fmt(hi), left + plotW, h - 3);
  ctx.fillStyle = '#ffa000';
  ctx.textAlign = 'center';
  ctx.fillText('margin', Math.min(Math.max(mx, left + 20), left + plotW - 40), h - 3);
}
