// SPDX-License-Identifier: MIT
// Forward kinematics in the page, as src/scene/kinematics.cpp computes it:
// a chain's transform is the product A1 * A2 * ... * Ak of its actions'
// transforms (metres, about the scene's origin), each action posed from its
// parameters as written (whole turns removed first, then to rad or m). The
// page carries the checker's own transforms at some states of each plan
// (checker_poses); poseDeviation compares the two, so a drift between this
// file and the checker shows on the page (and fails the browser tests).

// x mod whole_turn into [-whole_turn/2, whole_turn/2] (C's remainder but for
// exact ties, where both ends pose alike): % is exact in binary floating point.
function remainder(x, turn) {
  let r = x % turn;
  if (r > turn / 2) r -= turn;
  else if (r < -turn / 2) r += turn;
  return r;
}

function poseValue(a, written) {
  return a.whole_turn > 0 ? remainder(written, a.whole_turn) * a.unit_to_si : written * a.unit_to_si;
}

// 3 x 4 row-major affine transforms as plain arrays.
function multiply(a, b) {
  const out = new Array(12);
  for (let i = 0; i < 3; ++i) {
    for (let j = 0; j < 4; ++j) {
      let v = a[i * 4] * b[j] + a[i * 4 + 1] * b[4 + j] + a[i * 4 + 2] * b[8 + j];
      if (j === 3) v += a[i * 4 + 3];
      out[i * 4 + j] = v;
    }
  }
  return out;
}

const IDENTITY = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0];

// One action's transform; params: the full state, p0: its offset in `params`.
function actionTransform(actions, a, params, p0) {
  let value;
  if (a.mimic >= 0) value = a.multiplier * params[p0 + actions[a.mimic].first_parameter] + a.offset;
  else value = params[p0 + a.first_parameter];
  switch (a.type) {
    case 'rotate': {
      // x' = R(u, angle)(x - p) + p (Rodrigues' formula, as Eigen's AngleAxis).
      const t = poseValue(a, value), c = Math.cos(t), s = Math.sin(t), k = 1 - c;
      const [x, y, z] = a.axis, [px, py, pz] = a.pivot;
      const r = [c + x * x * k, x * y * k - z * s, x * z * k + y * s,
        y * x * k + z * s, c + y * y * k, y * z * k - x * s,
        z * x * k - y * s, z * y * k + x * s, c + z * z * k];
      return [r[0], r[1], r[2], px - (r[0] * px + r[1] * py + r[2] * pz),
        r[3], r[4], r[5], py - (r[3] * px + r[4] * py + r[5] * pz),
        r[6], r[7], r[8], pz - (r[6] * px + r[7] * py + r[8] * pz)];
    }
    case 'translate_axis': {
      const d = poseValue(a, value);
      return [1, 0, 0, a.axis[0] * d, 0, 1, 0, a.axis[1] * d, 0, 0, 1, a.axis[2] * d];
    }
    case 'translate': {
      const q = p0 + a.first_parameter;
      return [1, 0, 0, poseValue(a, params[q]), 0, 1, 0, poseValue(a, params[q + 1]), 0, 0, 1, poseValue(a, params[q + 2])];
    }
    case 'scale': {
      const q = p0 + a.first_parameter, f = a.fixed_point;
      const sx = params[q], sy = params[q + 1], sz = params[q + 2];
      return [sx, 0, 0, f[0] - sx * f[0], 0, sy, 0, f[1] - sy * f[1], 0, 0, sz, f[2] - sz * f[2]];
    }
    default:
      throw new Error(`unknown action type ${a.type}`);
  }
}

// Every chain's transform in page coordinates at the state starting at
// params[p0]: y -> R y + (R c + t - c) / unit (PageFrame::affine), appended
// to `out` (12 numbers per chain).
export function chainPoses(data, params, p0, out) {
  const c = data.centre_m, u = data.unit_m;
  const memo = new Map();
  data.chain_actions.forEach((chain, ci) => {
    let m = IDENTITY;
    for (const k of chain) {
      if (!memo.has(k)) memo.set(k, actionTransform(data.actions, data.actions[k], params, p0));
      m = multiply(m, memo.get(k));
    }
    for (let i = 0; i < 3; ++i) {
      const rc = m[i * 4] * c[0] + m[i * 4 + 1] * c[1] + m[i * 4 + 2] * c[2];
      out[ci * 12 + i * 4] = m[i * 4];
      out[ci * 12 + i * 4 + 1] = m[i * 4 + 1];
      out[ci * 12 + i * 4 + 2] = m[i * 4 + 2];
      out[ci * 12 + i * 4 + 3] = (rc + m[i * 4 + 3] - c[i]) / u;
    }
  });
  return out;
}

// The largest difference between the page's poses and the checker's at the
// states the page carries them for (checker: states, transforms as float32).
export function poseDeviation(data, params, checker) {
  const nparams = data.parameter_names.length, nchains = data.chain_actions.length;
  const mine = new Array(nchains * 12);
  let worst = 0;
  checker.states.forEach((s, k) => {
    chainPoses(data, params, s * nparams, mine);
    for (let i = 0; i < nchains * 12; ++i) worst = Math.max(worst, Math.abs(mine[i] - checker.transforms[k * nchains * 12 + i]));
  });
  return worst;
}
