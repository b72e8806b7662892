// The interactive arm of a rankloci HTML report.  Written for this project; no library.
//
// The page embeds, as JSON in <script id="rankloci-data">, the model's numeric chain (4x4
// transforms row by row, joint axes, which variable moves each joint and by what multiple)
// and, for each component of the locus, the joints its sliders move, the joints that follow
// them, a sample point, the solved values of the other joints and its equations, each as a
// JavaScript expression in the joint variables q[0..n-1] with the parameters replaced by
// their values.
//
// Forward kinematics, the geometric Jacobian at the tool point and its singular values are
// computed here, from the chain alone: the ratio sigma_min/sigma_max shown is not taken from
// the locus computation.  A pose is put on a component by setting the slider joints,
// evaluating the solved values, and moving the joints that follow by Gauss-Newton steps
// (least-norm, on the component's equations) from the previous pose.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("rankloci-data").textContent);
  const chain = data.chain;
  const n = chain.variables.length;
  // the gradients of the model's constraint functions: rows under the task rows of J
  const augment = chain.augment.map((row) =>
    row.map((code) => new Function("q", "return " + code + ";")));

  // ---- 4x4 transforms, row-major arrays of 16 numbers ----
  function mul(A, B) {
    const C = new Array(16).fill(0);
    for (let i = 0; i < 4; i++)
      for (let k = 0; k < 4; k++) {
        const a = A[4 * i + k];
        if (a === 0) continue;
        for (let j = 0; j < 4; j++) C[4 * i + j] += a * B[4 * k + j];
      }
    return C;
  }
  function motion(kind, axis, x) {
    const [ux, uy, uz] = axis;
    if (kind === "prismatic")
      return [1, 0, 0, ux * x, 0, 1, 0, uy * x, 0, 0, 1, uz * x, 0, 0, 0, 1];
    const c = Math.cos(x), s = Math.sin(x), v = 1 - c;
    return [c + ux * ux * v, ux * uy * v - uz * s, ux * uz * v + uy * s, 0,
            uy * ux * v + uz * s, c + uy * uy * v, uy * uz * v - ux * s, 0,
            uz * ux * v - uy * s, uz * uy * v + ux * s, c + uz * uz * v, 0,
            0, 0, 0, 1];
  }
  const origin = (T) => [T[3], T[7], T[11]];
  const rotate = (T, u) => [T[0] * u[0] + T[1] * u[1] + T[2] * u[2],
                            T[4] * u[0] + T[5] * u[1] + T[6] * u[2],
                            T[8] * u[0] + T[9] * u[1] + T[10] * u[2]];
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]];

  // Every frame origin along the chain (for drawing), each joint's origin and axis in the
  // world frame, and the tool frame.
  function kinematics(q) {
    let T = chain.base.slice();
    const points = [origin(T)], joints = [];
    for (const j of chain.joints) {
      T = mul(T, j.pre);
      points.push(origin(T));
      joints.push({o: origin(T), w: rotate(T, j.axis), kind: j.kind, v: j.variable,
                   m: j.multiplier});
      T = mul(mul(T, motion(j.kind, j.axis, j.multiplier * q[j.variable])), j.post);
      points.push(origin(T));
    }
    T = mul(T, chain.tool);
    points.push(origin(T));
    return {points, joints, tool: T};
  }

  // The geometric Jacobian (linear velocity of the tool point, then angular velocity), in the
  // world frame or the tool frame, rows of the task only; one column per variable.
  function jacobian(q) {
    const K = kinematics(q), p = origin(K.tool);
    const cols = [];
    for (let v = 0; v < n; v++) cols.push([0, 0, 0, 0, 0, 0]);
    for (const j of K.joints) {
      const lin = j.kind === "prismatic" ? j.w : cross(j.w, sub(p, j.o));
      const ang = j.kind === "prismatic" ? [0, 0, 0] : j.w;
      const c = cols[j.v];
      for (let r = 0; r < 3; r++) { c[r] += j.m * lin[r]; c[r + 3] += j.m * ang[r]; }
    }
    if (chain.frame === "tool") {   // R^T v, R^T w
      const T = K.tool, Rt = [T[0], T[4], T[8], T[1], T[5], T[9], T[2], T[6], T[10], 0, 0, 0];
      for (const c of cols) {
        const a = rotate(Rt, c.slice(0, 3)), b = rotate(Rt, c.slice(3, 6));
        for (let r = 0; r < 3; r++) { c[r] = a[r]; c[r + 3] = b[r]; }
      }
    }
    return chain.task.map((r) => cols.map((c) => c[r])).concat(augment.map((row) =>
      row.map((f) => f(q))));
  }

  // Singular values of an m x n matrix (array of rows) by one-sided Jacobi rotations on the
  // columns of whichever of A and A^T is tall; in decreasing order.
  function singularValues(A) {
    let m = A.length, k = A[0].length;
    let cols = [];
    if (m >= k) for (let j = 0; j < k; j++) cols.push(A.map((row) => row[j]));
    else { cols = A.map((row) => row.slice()); [m, k] = [k, m]; }
    for (let sweep = 0; sweep < 60; sweep++) {
      let rotated = false;
      for (let i = 0; i < k - 1; i++)
        for (let j = i + 1; j < k; j++) {
          const a = cols[i], b = cols[j];
          let alpha = 0, beta = 0, gamma = 0;
          for (let r = 0; r < m; r++) { alpha += a[r] * a[r]; beta += b[r] * b[r];
                                        gamma += a[r] * b[r]; }
          if (Math.abs(gamma) <= 1e-15 * Math.sqrt(alpha * beta) || gamma === 0) continue;
          rotated = true;
          const zeta = (beta - alpha) / (2 * gamma);
          const t = Math.sign(zeta || 1) / (Math.abs(zeta) + Math.sqrt(1 + zeta * zeta));
          const c = 1 / Math.sqrt(1 + t * t), s = c * t;
          for (let r = 0; r < m; r++) {
            const x = a[r], y = b[r];
            a[r] = c * x - s * y; b[r] = s * x + c * y;
          }
        }
      if (!rotated) break;
    }
    return cols.map((c) => Math.hypot(...c)).sort((x, y) => y - x);
  }

  // ---- keeping a pose on a component ----
  const components = data.components.map((c) => ({
    ...c,
    solvedFns: c.solved.map(([v, code]) => [v, new Function("q", "return " + code + ";")]),
    eqFns: c.equations.map((code) => new Function("q", "return " + code + ";")),
  }));

  // Least-norm Gauss-Newton on the equations, moving only the variables in `moving`;
  // derivatives by central differences.  Returns the largest residual left.
  // Residuals are divided by each equation's scale (the sum of its coefficients' sizes).
  function project(comp, q, moving) {
    const residual = () => comp.eqFns.map((f, e) => f(q) / comp.scales[e]);
    let res = residual();
    for (let it = 0; it < 50 && moving.length; it++) {
      if (Math.max(...res.map(Math.abs)) < 1e-14) break;
      const J = res.map(() => new Array(moving.length).fill(0));
      moving.forEach((v, k) => {
        const h = 1e-7, keep = q[v];
        q[v] = keep + h; const up = residual();
        q[v] = keep - h; const down = residual();
        q[v] = keep;
        for (let e = 0; e < res.length; e++) J[e][k] = (up[e] - down[e]) / (2 * h);
      });
      // step = -J^T (J J^T + mu I)^-1 res, by Gaussian elimination on the small system
      const m = res.length, G = [];
      for (let a = 0; a < m; a++) {
        G.push([]);
        for (let b = 0; b < m; b++) {
          let s = 0;
          for (let k = 0; k < moving.length; k++) s += J[a][k] * J[b][k];
          G[a].push(s + (a === b ? 1e-14 : 0));
        }
        G[a].push(-res[a]);
      }
      for (let p = 0; p < m; p++) {
        let best = p;
        for (let r = p + 1; r < m; r++) if (Math.abs(G[r][p]) > Math.abs(G[best][p])) best = r;
        [G[p], G[best]] = [G[best], G[p]];
        if (G[p][p] === 0) continue;
        for (let r = 0; r < m; r++) {
          if (r === p) continue;
          const f = G[r][p] / G[p][p];
          for (let c = p; c <= m; c++) G[r][c] -= f * G[p][c];
        }
      }
      const y = G.map((row, a) => (row[a] === 0 ? 0 : row[m] / row[a]));
      moving.forEach((v, k) => {
        let s = 0;
        for (let e = 0; e < m; e++) s += J[e][k] * y[e];
        q[v] += s;
      });
      res = residual();
    }
    return res.length ? Math.max(...res.map(Math.abs)) : 0;
  }

  function poseOn(comp, q, sliders) {
    for (const [v, x] of sliders) q[v] = x;
    for (const [v, f] of comp.solvedFns) q[v] = f(q);
    const moving = comp.moving;
    return project(comp, q, moving);
  }

  // ---- drawing: an orthographic view turned by dragging ----
  const canvas = document.getElementById("arm-canvas");
  const ctx = canvas.getContext("2d");
  // a planar arm is seen from above, a spatial one from the side
  const view = {azimuth: chain.planar ? 0 : 0.6, elevation: chain.planar ? 1.5 : 0.35};
  const reach = chain.reach;

  function project2d(p) {
    const ca = Math.cos(view.azimuth), sa = Math.sin(view.azimuth);
    const ce = Math.cos(view.elevation), se = Math.sin(view.elevation);
    const x = ca * p[0] + sa * p[1];
    const y = -sa * p[0] + ca * p[1];
    const up = ce * p[2] - se * y;
    const scale = (chain.planar ? 0.45 : 0.5) * Math.min(canvas.width, canvas.height) / reach;
    return [canvas.width / 2 + scale * x, canvas.height * (chain.planar ? 0.5 : 0.6) - scale * up];
  }

  function draw(q) {
    const K = kinematics(q);
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    // the floor: a square grid in the base plane
    ctx.strokeStyle = "#d8d8d8"; ctx.lineWidth = 1;
    for (let i = -4; i <= 4; i++) {
      const t = (i / 4) * reach;
      for (const [a, b] of [[[t, -reach, 0], [t, reach, 0]], [[-reach, t, 0], [reach, t, 0]]]) {
        const A = project2d(a), B = project2d(b);
        ctx.beginPath(); ctx.moveTo(A[0], A[1]); ctx.lineTo(B[0], B[1]); ctx.stroke();
      }
    }
    // the base: a square plate under the first frame
    const b = K.points[0], r = 0.08 * reach;
    const plate = [[-r, -r], [r, -r], [r, r], [-r, r]].map(([x, y]) =>
      project2d([b[0] + x, b[1] + y, b[2]]));
    ctx.fillStyle = "#9aa5b1";
    ctx.beginPath(); ctx.moveTo(plate[0][0], plate[0][1]);
    for (const p of plate.slice(1)) ctx.lineTo(p[0], p[1]);
    ctx.closePath(); ctx.fill();
    const pts = K.points.map(project2d);
    ctx.strokeStyle = "#1f4e79"; ctx.lineWidth = 5; ctx.lineCap = "round";
    ctx.beginPath(); ctx.moveTo(pts[0][0], pts[0][1]);
    for (const p of pts.slice(1)) ctx.lineTo(p[0], p[1]);
    ctx.stroke();
    const drawn = [];
    K.joints.forEach((j, i) => {
      const P = project2d(j.o);
      const A = project2d([j.o[0] + 0.12 * reach * j.w[0], j.o[1] + 0.12 * reach * j.w[1],
                           j.o[2] + 0.12 * reach * j.w[2]]);
      ctx.strokeStyle = "#b0b0b0"; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.moveTo(P[0], P[1]); ctx.lineTo(A[0], A[1]); ctx.stroke();
      ctx.fillStyle = j.kind === "prismatic" ? "#8a5a00" : "#c0392b";
      ctx.beginPath();
      if (j.kind === "prismatic") ctx.rect(P[0] - 6, P[1] - 6, 12, 12);
      else ctx.arc(P[0], P[1], 6, 0, 2 * Math.PI);
      ctx.fill();
      ctx.fillStyle = "#000"; ctx.font = "12px sans-serif";
      ctx.fillText(String(i + 1), P[0] + 8, P[1] - 8);
      drawn.push([+P[0].toFixed(2), +P[1].toFixed(2)]);
    });
    // the end-effector frame: x red, y green, z blue
    const e = origin(K.tool), E = project2d(e);
    [[1, 0, 0], [0, 1, 0], [0, 0, 1]].forEach((u, k) => {
      const w = rotate(K.tool, u), l = 0.1 * reach;
      const A = project2d([e[0] + l * w[0], e[1] + l * w[1], e[2] + l * w[2]]);
      ctx.strokeStyle = ["#d62728", "#2ca02c", "#1f77b4"][k]; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.moveTo(E[0], E[1]); ctx.lineTo(A[0], A[1]); ctx.stroke();
    });
    const tip = project2d(origin(K.tool));
    ctx.fillStyle = "#2e7d32"; ctx.beginPath(); ctx.arc(tip[0], tip[1], 5, 0, 2 * Math.PI);
    ctx.fill();
    drawn.push([+tip[0].toFixed(2), +tip[1].toFixed(2)]);
    canvas.dataset.joints = JSON.stringify(drawn);
  }

  // ---- the controls ----
  const select = document.getElementById("arm-component");
  const slidersBox = document.getElementById("arm-sliders");
  const ratioOut = document.getElementById("sigma-ratio");
  const residualOut = document.getElementById("arm-residual");
  const poseOut = document.getElementById("arm-pose");
  let q = chain.sample.slice();
  let current = null;

  // Is variable k within its limits at x (an angle: some whole number of turns away)?
  function within(k, x) {
    const lim = chain.limits[k];
    if (!lim) return true;
    if (chain.prismatic[k]) return lim[0] <= x && x <= lim[1];
    const turn = 2 * Math.PI, y = lim[0] + ((((x - lim[0]) % turn) + turn) % turn);
    return y <= lim[1] + 1e-12;
  }

  function fmt(x) { return Math.abs(x) < 5e-13 ? "0" : x.toPrecision(4); }

  function update() {
    const sliders = [];
    if (current)
      for (const input of slidersBox.querySelectorAll("input[type=range]"))
        sliders.push([+input.dataset.variable, +input.value]);
    let residual = 0;
    if (current) residual = poseOn(current, q, sliders);
    residualOut.dataset.value = String(residual);
    for (const input of slidersBox.querySelectorAll("input[type=range]"))
      input.nextElementSibling.textContent = fmt(+input.value) + " " + input.dataset.unit;
    const s = singularValues(jacobian(q));
    const ratio = s[s.length - 1] / s[0];
    ratioOut.textContent = ratio.toExponential(2) + (ratio <= chain.rtol
      ? " (rank deficient: at most " + chain.rtol.toExponential(0) + ")" : " (full rank)");
    ratioOut.dataset.value = String(ratio);
    residualOut.textContent = !(current && current.index) ? "(no equations)"
      : residual.toExponential(1) + (residual > 1e-9
        ? " (the joints that follow could not reach the component here: move back)" : "");
    poseOut.dataset.value = JSON.stringify(q);
    const outside = chain.variables.filter((_, i) => !within(i, q[i]));
    poseOut.dataset.outside = JSON.stringify(outside);
    poseOut.textContent = chain.variables.map((name, i) =>
      name + " = " + fmt(q[i]) + (chain.prismatic[i] ? " m" : "")).join(", ")
      + (outside.length ? "; outside the joint limits: " + outside.join(", ") : "");
    draw(q);
  }

  function choose(index) {
    current = components.find((c) => c.index === index) || null;
    slidersBox.textContent = "";
    if (!current) return;
    q = current.sample.slice();
    for (const v of current.sliders) {
      const label = document.createElement("label");
      const name = document.createElement("span");
      name.textContent = chain.variables[v];
      name.className = "slider-name";
      const input = document.createElement("input");
      input.type = "range";
      const [lo, hi] = chain.ranges[v];
      input.min = String(lo); input.max = String(hi);
      input.step = String((hi - lo) / 400);
      input.value = String(q[v]);
      input.dataset.variable = String(v);
      input.dataset.unit = chain.prismatic[v] ? "m" : "rad";
      input.id = "slider-" + current.index + "-" + chain.variables[v];
      input.addEventListener("input", update);
      const value = document.createElement("output");
      label.append(name, input, value);
      slidersBox.append(label);
    }
    update();
  }

  // "every joint free": no component, a slider per joint, nothing keeps the pose on the locus
  components.unshift({index: 0, sliders: chain.variables.map((_, k) => k), sample: chain.sample,
                      solvedFns: [], eqFns: [], scales: [], moving: []});
  for (const c of components) {
    const option = document.createElement("option");
    option.value = String(c.index);
    option.textContent = c.index === 0 ? "none: every joint free"
      : "Component " + c.index + (c.outside ? " (outside the joint limits)" : "")
        + (c.sliders.length ? "" : " (no free joint)");
    select.append(option);
  }
  select.addEventListener("change", () => choose(+select.value));

  let drag = null;
  canvas.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY]; });
  window.addEventListener("pointerup", () => { drag = null; });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    view.azimuth -= 0.01 * (e.clientX - drag[0]);
    view.elevation = Math.max(-1.5, Math.min(1.5, view.elevation + 0.01 * (e.clientY - drag[1])));
    drag = [e.clientX, e.clientY];
    draw(q);
  });

  const first = components.length > 1 ? components[1].index : 0;
  select.value = String(first);
  choose(first);
})();
