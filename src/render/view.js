// The replay of a simulated run (kbc run --view). Written for kbc; see src/render/view.rs.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("run-data").textContent);
  const record = data.record;
  const frames = record.frames;
  const actions = data.actions;
  const faults = record.faults || [];
  const cell = record.cell_size;
  const half = record.block_size / 2;
  const end = frames.length ? frames[frames.length - 1].t : 0;
  const cells = new Set(record.cells.map(([x, y]) => x + "," + y));

  // ---- time: the frame at t, positions interpolated between samples ----
  function frameIndex(t) {
    let lo = 0;
    let hi = frames.length - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (frames[mid].t <= t) lo = mid;
      else hi = mid - 1;
    }
    return lo;
  }
  function lerp(a, b, s) {
    return a.map((v, i) => (i < 3 ? v + (b[i] - v) * s : v));
  }
  function poseAt(t) {
    const i = frameIndex(t);
    const a = frames[i];
    const b = frames[Math.min(i + 1, frames.length - 1)];
    const s = b.t > a.t ? Math.min(1, Math.max(0, (t - a.t) / (b.t - a.t))) : 0;
    return {
      blocks: a.blocks.map((p, k) => lerp(p, b.blocks[k], s)),
      grippers: a.grippers.map((p, k) => lerp(p, b.grippers[k], s)),
      elbows: (a.elbows || []).map((p, k) => lerp(p, b.elbows[k], s)),
    };
  }

  // ---- where a block is, as the run's read-back would say ----
  function placement(p, pose) {
    const [x, y, z] = p;
    const cx = Math.round(x / cell);
    const cy = Math.round(y / cell);
    const onCell = Math.abs(x - cx * cell) < cell / 3 && Math.abs(y - cy * cell) < cell / 3 && cells.has(cx + "," + cy);
    const holder = pose.grippers.findIndex((g) => Math.hypot(g[0] - x, g[1] - y) < half && Math.abs(g[2] - (z + half)) < 2 * half);
    if (holder >= 0 && z > half * 1.5) return { text: "held by " + record.arms[holder] };
    const level = Math.round((z - half) / (2 * half));
    if (onCell && Math.abs(z - half - level * 2 * half) < 0.01 && level >= 0) {
      return { cell: cx + "," + cy, level: level, text: "cell (" + cx + ", " + cy + ")" + (level ? ", level " + level : ", on the table") };
    }
    if (z < 0) return { text: "off the table" };
    return { text: "between cells" };
  }

  // ---- the scene's extent, over the whole run ----
  const xs = [];
  const ys = [];
  const zs = [0];
  for (const [cx, cy] of record.cells) {
    xs.push((cx - 0.5) * cell, (cx + 0.5) * cell);
    ys.push((cy - 0.5) * cell, (cy + 0.5) * cell);
  }
  for (const s of record.shoulders) {
    xs.push(s[0]);
    ys.push(s[1]);
    zs.push(s[2]);
  }
  for (const f of frames) {
    for (const p of f.blocks.concat(f.grippers, f.elbows || [])) {
      xs.push(p[0]);
      ys.push(p[1]);
      zs.push(p[2] + half);
    }
  }
  // (A loop, not Math.min(...xs): a long run has more values than a call takes arguments.)
  const least = (values) => values.reduce((a, b) => Math.min(a, b), Infinity);
  const most = (values) => values.reduce((a, b) => Math.max(a, b), -Infinity);
  const margin = 0.06;
  const box = {
    x0: least(xs) - margin, x1: most(xs) + margin,
    y0: least(ys) - margin, y1: most(ys) + margin,
    z0: -0.04, z1: most(zs) + margin,
  };

  // ---- colours: one hue per block, darker the higher it stands ----
  function blockColour(k, level) {
    const hue = (k * 137.508) % 360;
    const light = Math.max(35, 72 - 9 * level);
    return "hsl(" + hue.toFixed(0) + ", 55%, " + light + "%)";
  }
  const armColour = ["#333", "#7a3b8f", "#1f6f8b", "#8b5a1f", "#2f7d32", "#a23b3b", "#555f99", "#6b6b2a"];

  function yaw(q) {
    const [qx, qy, qz, qw] = q;
    return Math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz));
  }

  // ---- drawing ----
  function fit(canvas, u0, u1, v0, v1) {
    const pad = 14;
    const scale = Math.min((canvas.width - 2 * pad) / (u1 - u0), (canvas.height - 2 * pad) / (v1 - v0));
    const ox = (canvas.width - scale * (u1 - u0)) / 2;
    const oy = (canvas.height - scale * (v1 - v0)) / 2;
    return {
      scale: scale,
      u: (u) => ox + (u - u0) * scale,
      v: (v) => canvas.height - oy - (v - v0) * scale,
    };
  }

  const top = document.getElementById("top");
  const side = document.getElementById("side");
  const topView = fit(top, box.x0, box.x1, box.y0, box.y1);
  const sideView = fit(side, box.x0, box.x1, box.z0, box.z1);

  function label(ctx, text, x, y, size) {
    ctx.font = size + "px sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "middle";
    ctx.lineWidth = 3;
    ctx.strokeStyle = "rgba(255,255,255,0.85)";
    ctx.strokeText(text, x, y);
    ctx.fillStyle = "#111";
    ctx.fillText(text, x, y);
  }

  function drawArm(ctx, view, k, points) {
    ctx.strokeStyle = armColour[k % armColour.length];
    ctx.lineWidth = 5;
    ctx.lineCap = "round";
    ctx.lineJoin = "round";
    ctx.beginPath();
    points.forEach(([u, v], i) => (i ? ctx.lineTo(view.u(u), view.v(v)) : ctx.moveTo(view.u(u), view.v(v))));
    ctx.stroke();
    const [gu, gv] = points[points.length - 1];
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(view.u(gu), view.v(gv), 5, 0, 2 * Math.PI);
    ctx.fillStyle = "#fff";
    ctx.fill();
    ctx.stroke();
  }

  function drawTop(pose) {
    const ctx = top.getContext("2d");
    const v = topView;
    ctx.clearRect(0, 0, top.width, top.height);
    // The table's cells, with their coordinates.
    for (const [cx, cy] of record.cells) {
      const x = v.u((cx - 0.5) * cell);
      const y = v.v((cy + 0.5) * cell);
      ctx.fillStyle = "#e9e4d8";
      ctx.fillRect(x + 1, y + 1, cell * v.scale - 2, cell * v.scale - 2);
      ctx.fillStyle = "#9a927f";
      ctx.font = "10px sans-serif";
      ctx.textAlign = "left";
      ctx.textBaseline = "top";
      ctx.fillText(cx + "," + cy, x + 4, y + 3);
    }
    // Blocks, lowest first, so a stack shows its top block.
    const order = pose.blocks.map((p, k) => k).sort((a, b) => pose.blocks[a][2] - pose.blocks[b][2]);
    const s = 2 * half * v.scale;
    for (const k of order) {
      const p = pose.blocks[k];
      const level = Math.max(0, Math.round((p[2] - half) / (2 * half)));
      ctx.save();
      ctx.translate(v.u(p[0]), v.v(p[1]));
      ctx.rotate(-yaw(p.slice(3)));
      ctx.fillStyle = blockColour(k, level);
      ctx.strokeStyle = "#333";
      ctx.lineWidth = 1;
      ctx.fillRect(-s / 2, -s / 2, s, s);
      ctx.strokeRect(-s / 2, -s / 2, s, s);
      ctx.restore();
    }
    // Arms: base, elbow, gripper, seen from above.
    record.shoulders.forEach((sh, k) => {
      const points = [[sh[0], sh[1]]];
      if (pose.elbows[k]) points.push([pose.elbows[k][0], pose.elbows[k][1]]);
      points.push([pose.grippers[k][0], pose.grippers[k][1]]);
      drawArm(ctx, v, k, points);
      ctx.fillStyle = armColour[k % armColour.length];
      ctx.beginPath();
      ctx.arc(v.u(sh[0]), v.v(sh[1]), 9, 0, 2 * Math.PI);
      ctx.fill();
      label(ctx, record.arms[k], v.u(sh[0]), v.v(sh[1]) + 18, 12);
    });
    // Names last, over the arms: the top block of each stack, offset when a gripper is on it.
    const named = new Set();
    for (const k of order.slice().reverse()) {
      const p = pose.blocks[k];
      const key = Math.round(p[0] / half) + "," + Math.round(p[1] / half);
      if (named.has(key)) continue;
      named.add(key);
      label(ctx, record.blocks[k], v.u(p[0]), v.v(p[1]) - s / 2 - 8, 12);
    }
  }

  function drawSide(pose) {
    const ctx = side.getContext("2d");
    const v = sideView;
    ctx.clearRect(0, 0, side.width, side.height);
    // The table top, and the cells' extent along x.
    ctx.fillStyle = "#d9d2c0";
    ctx.fillRect(v.u(box.x0), v.v(0), (box.x1 - box.x0) * v.scale, 0.03 * v.scale);
    const columns = [...new Set(record.cells.map(([cx]) => cx))];
    ctx.fillStyle = "#9a927f";
    ctx.font = "10px sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "top";
    for (const cx of columns) ctx.fillText("x=" + cx, v.u(cx * cell), v.v(0) + 0.03 * v.scale + 2);
    // Blocks, farthest (largest y) first.
    const order = pose.blocks.map((p, k) => k).sort((a, b) => pose.blocks[b][1] - pose.blocks[a][1]);
    const s = 2 * half * v.scale;
    for (const k of order) {
      const p = pose.blocks[k];
      const level = Math.max(0, Math.round((p[2] - half) / (2 * half)));
      ctx.fillStyle = blockColour(k, level);
      ctx.strokeStyle = "#333";
      ctx.lineWidth = 1;
      ctx.fillRect(v.u(p[0]) - s / 2, v.v(p[2]) - s / 2, s, s);
      ctx.strokeRect(v.u(p[0]) - s / 2, v.v(p[2]) - s / 2, s, s);
      label(ctx, record.blocks[k], v.u(p[0]), v.v(p[2]), 11);
    }
    record.shoulders.forEach((sh, k) => {
      const points = [[sh[0], sh[2]]];
      if (pose.elbows[k]) points.push([pose.elbows[k][0], pose.elbows[k][2]]);
      points.push([pose.grippers[k][0], pose.grippers[k][2]]);
      ctx.strokeStyle = "#bbb";
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.moveTo(v.u(sh[0]), v.v(0));
      ctx.lineTo(v.u(sh[0]), v.v(sh[2]));
      ctx.stroke();
      drawArm(ctx, v, k, points);
      label(ctx, record.arms[k], v.u(sh[0]), v.v(sh[2]) - 14, 12);
    });
  }

  // ---- the text beside the pictures ----
  function fmt(t) {
    return t.toFixed(2) + " s";
  }
  function listInto(id, items) {
    const list = document.getElementById(id);
    list.replaceChildren(
      ...items.map(([text, cls]) => {
        const li = document.createElement("li");
        li.textContent = text;
        if (cls) li.className = cls;
        return li;
      }),
    );
  }
  function describe(t, pose) {
    const running = actions
      .filter((a) => a.start <= t && (t < a.end || (a.ending !== "done" && Math.abs(t - a.end) < 1e-9)))
      .map((a) => [
        (a.arm ? a.arm + ": " : "") + a.text + " (" + fmt(t - a.start) + " of " + fmt(a.end - a.start) + (a.ending === "done" ? ")" : ", then " + a.ending + ")"),
        a.ending === "done" ? "" : "failed",
      ]);
    listInto("running", running.length ? running : [["nothing", "past"]]);
    listInto(
      "faults",
      faults.length ? faults.map((f) => [fmt(f.t) + ": " + f.what, f.t <= t ? "fault" : "past"]) : [["none", "past"]],
    );
    const rows = pose.blocks.map((p, k) => {
      const where = placement(p, pose);
      const tr = document.createElement("tr");
      tr.dataset.block = record.blocks[k];
      if (where.cell) {
        tr.dataset.cell = where.cell;
        tr.dataset.level = String(where.level);
      }
      const cellsOf = [record.blocks[k], p[0].toFixed(3), p[1].toFixed(3), p[2].toFixed(3), where.text];
      cellsOf.forEach((text, i) => {
        const td = document.createElement("td");
        td.textContent = text;
        if (i >= 1 && i <= 3) td.className = "num";
        tr.appendChild(td);
      });
      return tr;
    });
    document.querySelector("#readout tbody").replaceChildren(...rows);
  }

  // ---- the chart's time cursor, and fault marks on the slider ----
  const svg = document.querySelector("#gantt svg");
  let cursor = null;
  if (svg && svg.dataset.span) {
    cursor = document.createElementNS("http://www.w3.org/2000/svg", "line");
    cursor.setAttribute("stroke", "#000");
    cursor.setAttribute("stroke-width", "1.5");
    cursor.setAttribute("y1", svg.dataset.y0);
    cursor.setAttribute("y2", svg.dataset.y1);
    svg.appendChild(cursor);
  }
  function moveCursor(t) {
    if (!cursor) return;
    const x0 = Number(svg.dataset.x0);
    const x1 = Number(svg.dataset.x1);
    const span = Number(svg.dataset.span) / record.units_per_second;
    const x = x0 + (Math.min(t, span) / span) * (x1 - x0);
    cursor.setAttribute("x1", x);
    cursor.setAttribute("x2", x);
  }
  const marks = document.getElementById("marks");
  for (const f of faults) {
    const m = document.createElement("span");
    m.style.left = (end > 0 ? (100 * f.t) / end : 0) + "%";
    m.title = fmt(f.t) + ": " + f.what;
    marks.appendChild(m);
  }

  // ---- the clock ----
  const slider = document.getElementById("slider");
  const clock = document.getElementById("clock");
  const play = document.getElementById("play");
  const speed = document.getElementById("speed");
  slider.max = String(end);
  let now = 0;
  let playing = false;
  let last = null;

  function countDrawn() {
    // Pixels the top view drew: a headless browser's check that the canvas renders.
    const pixels = top.getContext("2d").getImageData(0, 0, top.width, top.height).data;
    let drawn = 0;
    for (let i = 3; i < pixels.length; i += 4) if (pixels[i] !== 0) drawn++;
    return drawn;
  }

  function show(t) {
    now = Math.min(end, Math.max(0, t));
    const pose = poseAt(now);
    drawTop(pose);
    drawSide(pose);
    describe(now, pose);
    moveCursor(now);
    slider.value = String(now);
    clock.textContent = fmt(now) + " / " + fmt(end);
    document.body.dataset.time = now.toFixed(3);
    document.body.dataset.drawn = String(countDrawn());
  }

  function tick(stamp) {
    if (!playing) return;
    if (last !== null) show(now + ((stamp - last) / 1000) * Number(speed.value));
    last = stamp;
    if (now >= end) setPlaying(false);
    else requestAnimationFrame(tick);
  }
  function setPlaying(on) {
    playing = on;
    play.textContent = on ? "Pause" : "Play";
    last = null;
    if (on) {
      if (now >= end) show(0);
      requestAnimationFrame(tick);
    }
  }
  play.addEventListener("click", () => setPlaying(!playing));
  slider.addEventListener("input", () => {
    setPlaying(false);
    show(Number(slider.value));
  });
  document.addEventListener("keydown", (e) => {
    if (e.target instanceof HTMLSelectElement) return;
    const keys = { " ": () => setPlaying(!playing), ArrowLeft: () => show(now - 0.1), ArrowRight: () => show(now + 0.1), Home: () => show(0), End: () => show(end) };
    if (keys[e.key]) {
      e.preventDefault();
      if (e.key !== " ") setPlaying(false);
      keys[e.key]();
    }
  });

  // `#t=end`, `#t=mid` or `#t=SECONDS` opens the page at that moment.
  function fromHash() {
    const m = /(?:^#|&)t=([^&]+)/.exec(location.hash);
    if (!m) return 0;
    if (m[1] === "end") return end;
    if (m[1] === "mid") return end / 2;
    const t = Number(m[1]);
    return Number.isFinite(t) ? t : 0;
  }
  window.addEventListener("hashchange", () => show(fromHash()));
  show(fromHash());
})();
