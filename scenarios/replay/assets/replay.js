// robotstadium replay page: plays a match from the data embedded in #replay-data.
// The data format is described in scenarios/replay/data.py. No network: everything is inline.
"use strict";
(function () {
  const DATA = JSON.parse(document.getElementById("replay-data").textContent);
  const F = DATA.field, COLORS = DATA.colors, MATCH = DATA.match;
  const T = Float64Array.from(DATA.frames.t); // ms of simulated time, one per frame
  const NF = T.length, T0 = T[0], T1 = T[NF - 1];
  const SPEEDS = [0.5, 1, 2, 4, 8, 16];
  const JUMP_M = 0.4; // a robot or ball that moved more between two frames was placed: no interpolation
  const ROBOT_R = 0.13, NOSE = 0.27; // marker radius and heading length, metres
  const STATE_COLORS = { INITIAL: "#555d68", READY: "#2f6fb0", SET: "#b08a2f", PLAYING: "#2e8b4f", FINISHED: "#7a3a3a" };

  // Per-robot extras: a column of toggles each, shown only when some robot has the channel.
  const EXTRAS = [
    { name: "estimate", label: "estimate", title: "its own pose estimate, and the error line to the truth" },
    { name: "ball_estimate", label: "ball", title: "where it believes the ball is" },
    { name: "team_ball", label: "team ball", title: "the team's shared ball" },
    { name: "role", label: "role", title: "its role" },
    { name: "landmarks", label: "landmarks", title: "the landmarks it saw" },
  ];
  // Events marked on the timeline: lane (0 game, 1 ball, 2 robots), colour, label.
  const MARKS = {
    kickoff: [0, "#7bd389", "kick-off"],
    goal: [0, "#ffffff", "goal"],
    goal_disallowed: [0, "#b0b0b0", "goal disallowed"],
    half_time: [0, "#c792ea", "half-time"],
    shootout_kick: [0, "#ffd54f", "shoot-out kick"],
    end: [0, "#ef9a9a", "end"],
    ball_out: [1, "#ff9e40", "ball out"],
    fall: [2, "#ff5252", "fall"],
    robot_placed: [2, "#4fc3f7", "placed"],
    robot_replaced: [2, "#29b6f6", "replaced"],
    fault: [2, "#ea80fc", "fault"],
  };

  function decode(ch) {
    const v = new Float32Array(ch.data.length);
    for (let i = 0; i < v.length; i++) v[i] = ch.data[i] === null ? NaN : ch.data[i] / ch.scale;
    return { dims: ch.dims, v: v };
  }
  const clock = decode(DATA.frames.clock), ball = decode(DATA.frames.ball);
  const robots = DATA.robots.map(function (r) {
    const ch = {};
    for (const name in r.channels) ch[name] = decode(r.channels[name]);
    return { id: r.id, side: r.side, player: r.player, ch: ch, show: {} };
  });
  const extras = EXTRAS.filter(function (x) { return robots.some(function (r) { return x.name in r.ch; }); });
  const events = DATA.events.filter(function (e) { return e.kind in MARKS; });
  const status = DATA.status;

  // ---- time ----------------------------------------------------------------------------
  let now = T0, playing = false, speed = 1, lastTick = null, dirty = true;

  function frameAt(t) { // the last frame at or before t
    let lo = 0, hi = NF - 1;
    if (t <= T[0]) return 0;
    if (t >= T[hi]) return hi;
    while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (T[mid] <= t) lo = mid; else hi = mid - 1; }
    return lo;
  }
  function statusAt(t) {
    let lo = 0, hi = status.length - 1;
    while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (status[mid].t <= t) lo = mid; else hi = mid - 1; }
    return status[lo];
  }
  function seek(t) { now = Math.min(T1, Math.max(T0, t)); redraw(); }
  function redraw() { dirty = false; render(); } // at once, so that what a click changed is on screen when it returns
  function setPlaying(on) {
    if (on && now >= T1) now = T0;
    playing = on; lastTick = null; dirty = true;
    document.getElementById("play").classList.toggle("playing", on);
  }
  function stepFrame(d) {
    setPlaying(false);
    const f = frameAt(now);
    if (d < 0 && now > T[f]) seek(T[f]); else seek(T[Math.min(NF - 1, Math.max(0, f + d))]);
  }
  function setSpeed(s) { speed = s; document.getElementById("speed").value = String(s); }
  function fmtClock(s) { s = Math.max(0, Math.ceil(s - 1e-6)); return Math.floor(s / 60) + ":" + String(s % 60).padStart(2, "0"); }
  function fmtTime(ms) { const s = ms / 1000; return Math.floor(s / 60) + ":" + (s % 60).toFixed(1).padStart(4, "0"); }

  // ---- values at a time ----------------------------------------------------------------
  function lerpAngle(a, b, u) { let d = b - a; while (d > Math.PI) d -= 2 * Math.PI; while (d < -Math.PI) d += 2 * Math.PI; return a + d * u; }
  function sample(ch, f, u, interpolate) { // values of channel ch between frames f and f+1
    const d = ch.dims, out = new Array(d);
    for (let k = 0; k < d; k++) out[k] = ch.v[f * d + k];
    if (!interpolate || u <= 0 || f + 1 >= NF) return out;
    const nx = ch.v[(f + 1) * d], ny = ch.v[(f + 1) * d + 1];
    if (!(Math.hypot(nx - out[0], ny - out[1]) < JUMP_M)) return out;
    out[0] += (nx - out[0]) * u; out[1] += (ny - out[1]) * u;
    if (d >= 3) out[2] = lerpAngle(out[2], ch.v[(f + 1) * d + 2], u);
    return out;
  }
  function teamColor(robot, st) {
    const home = st.home_color === "red" ? "red" : "blue";
    const color = robot.side === "home" ? home : (home === "blue" ? "red" : "blue");
    return COLORS[color];
  }

  // ---- drawing ---------------------------------------------------------------------------
  const canvas = document.getElementById("field"), ctx = canvas.getContext("2d");
  const background = document.createElement("canvas");
  const HL = F.length / 2, HW = F.width / 2;
  const EXT_X = HL + F.carpet_margin + 0.15, EXT_Y = HW + F.carpet_margin + 0.15;
  let px = 100; // canvas pixels per metre
  function sx(x) { return (x + EXT_X) * px; }
  function sy(y) { return (EXT_Y - y) * px; }

  function resize() {
    const stage = document.getElementById("stage");
    const w = Math.max(200, stage.clientWidth - 12), h = Math.max(150, stage.clientHeight - 12);
    const cssScale = Math.min(w / (2 * EXT_X), h / (2 * EXT_Y));
    const dpr = window.devicePixelRatio || 1;
    const cw = Math.floor(2 * EXT_X * cssScale), chh = Math.floor(2 * EXT_Y * cssScale);
    canvas.style.width = cw + "px"; canvas.style.height = chh + "px";
    canvas.width = Math.round(cw * dpr); canvas.height = Math.round(chh * dpr);
    px = canvas.width / (2 * EXT_X);
    background.width = canvas.width; background.height = canvas.height;
    drawBackground(background.getContext("2d"));
    dirty = true;
  }

  function drawBackground(g) {
    g.fillStyle = COLORS.floor; g.fillRect(0, 0, background.width, background.height);
    const cx = HL + F.carpet_margin, cy = HW + F.carpet_margin;
    g.fillStyle = COLORS.carpet; g.fillRect(sx(-cx), sy(cy), 2 * cx * px, 2 * cy * px);
    g.strokeStyle = COLORS.line; g.lineWidth = F.line_width * px; g.lineCap = "square";
    for (const s of F.lines) { g.beginPath(); g.moveTo(sx(s[0]), sy(s[1])); g.lineTo(sx(s[2]), sy(s[3])); g.stroke(); }
    g.beginPath(); g.arc(sx(F.circle.x), sy(F.circle.y), F.circle.r * px, 0, 2 * Math.PI); g.stroke();
    for (const [sign, color] of [[-1, COLORS.blue_goal], [1, COLORS.yellow_goal]]) {
      const x0 = sign * HL, x1 = sign * (HL + F.goal_depth), y = F.goal_post_y;
      g.fillStyle = color; g.globalAlpha = 0.3;
      g.fillRect(Math.min(sx(x0), sx(x1)), sy(y), Math.abs(sx(x1) - sx(x0)), 2 * y * px);
      g.globalAlpha = 1; g.strokeStyle = color; g.lineWidth = Math.max(1.5, 0.03 * px); g.lineCap = "butt";
      g.beginPath(); g.moveTo(sx(x0), sy(y)); g.lineTo(sx(x1), sy(y)); g.lineTo(sx(x1), sy(-y)); g.lineTo(sx(x0), sy(-y)); g.stroke();
      g.fillStyle = color;
      for (const py of [-y, y]) { g.beginPath(); g.arc(sx(x0), sy(py), Math.max(3, F.goal_post_radius * px), 0, 2 * Math.PI); g.fill(); }
    }
  }

  function drawRobot(g, r, pose, color, fallen) {
    const x = sx(pose[0]), y = sy(pose[1]), th = pose[2], rad = Math.max(7, ROBOT_R * px);
    g.save(); g.translate(x, y); g.rotate(-th);
    if (fallen) { // lying on the ground: a long body along its heading, dashed outline
      g.globalAlpha = 0.75; g.fillStyle = color;
      g.beginPath(); g.rect(-rad * 2.1, -rad * 0.8, rad * 4.2, rad * 1.6); g.fill();
      g.globalAlpha = 1; g.setLineDash([4, 3]); g.strokeStyle = "#fff"; g.lineWidth = 1.5; g.stroke(); g.setLineDash([]);
    } else {
      g.fillStyle = color; g.strokeStyle = "#fff"; g.lineWidth = 1.5;
      g.beginPath(); g.moveTo(Math.max(NOSE * px, rad * 2), 0); g.lineTo(rad * 0.5, rad * 0.75); g.lineTo(rad * 0.5, -rad * 0.75); g.closePath();
      g.fill(); g.stroke();
      g.beginPath(); g.arc(0, 0, rad, 0, 2 * Math.PI); g.fill(); g.stroke();
    }
    g.restore();
    g.fillStyle = "#fff"; g.font = "bold " + Math.round(rad * 1.25) + "px sans-serif";
    g.textAlign = "center"; g.textBaseline = "middle";
    g.fillText(String(r.player), x, y + 1);
    if (fallen) { g.font = "bold " + Math.round(rad) + "px sans-serif"; g.fillStyle = "#ffebee"; g.fillText("fallen", x, y - rad * 1.6); }
  }

  function drawEstimate(g, truth, est, color) {
    const rad = Math.max(6, ROBOT_R * px);
    g.strokeStyle = "#fff59d"; g.lineWidth = 2; g.setLineDash([6, 4]);
    g.beginPath(); g.moveTo(sx(truth[0]), sy(truth[1])); g.lineTo(sx(est[0]), sy(est[1])); g.stroke(); g.setLineDash([]);
    const x = sx(est[0]), y = sy(est[1]);
    for (const [w, c] of [[5, "rgba(0,0,0,0.6)"], [2.5, color]]) {
      g.strokeStyle = c; g.lineWidth = w;
      g.beginPath(); g.arc(x, y, rad, 0, 2 * Math.PI); g.stroke();
      if (Number.isFinite(est[2])) { g.beginPath(); g.moveTo(x, y); g.lineTo(x + Math.cos(est[2]) * NOSE * px, y - Math.sin(est[2]) * NOSE * px); g.stroke(); }
    }
  }

  function drawExtras(g, r, f, truth, color) {
    const from = [sx(truth[0]), sy(truth[1])];
    if (r.show.landmarks && r.ch.landmarks) {
      const mask = r.ch.landmarks.v[f];
      if (Number.isFinite(mask)) {
        g.strokeStyle = color; g.globalAlpha = 0.55; g.lineWidth = 1.5;
        F.landmarks.forEach(function (lm, i) {
          if (Math.floor(mask / Math.pow(2, i)) % 2 === 1) {
            g.beginPath(); g.moveTo(from[0], from[1]); g.lineTo(sx(lm.x), sy(lm.y)); g.stroke();
            g.beginPath(); g.arc(sx(lm.x), sy(lm.y), 5, 0, 2 * Math.PI); g.stroke();
          }
        });
        g.globalAlpha = 1;
      }
    }
    if (r.show.ball_estimate && r.ch.ball_estimate) {
      const b = sample(r.ch.ball_estimate, f, 0, false);
      if (Number.isFinite(b[0])) {
        g.strokeStyle = color; g.lineWidth = 1.5; g.setLineDash([2, 3]);
        g.beginPath(); g.moveTo(from[0], from[1]); g.lineTo(sx(b[0]), sy(b[1])); g.stroke(); g.setLineDash([]);
        g.lineWidth = 3; g.beginPath(); g.arc(sx(b[0]), sy(b[1]), Math.max(5, 0.06 * px), 0, 2 * Math.PI); g.stroke();
      }
    }
    if (r.show.team_ball && r.ch.team_ball) {
      const b = sample(r.ch.team_ball, f, 0, false);
      if (Number.isFinite(b[0])) {
        const s = Math.max(6, 0.08 * px), x = sx(b[0]), y = sy(b[1]);
        g.strokeStyle = color; g.lineWidth = 2.5;
        g.beginPath(); g.moveTo(x, y - s); g.lineTo(x + s, y); g.lineTo(x, y + s); g.lineTo(x - s, y); g.closePath(); g.stroke();
      }
    }
  }

  function drawLabel(g, r, f, truth) {
    if (!(r.show.role && r.ch.role)) return;
    const v = r.ch.role.v[f];
    if (!Number.isFinite(v)) return;
    const names = (DATA.labels && DATA.labels.role) || [];
    const text = names[v] !== undefined ? names[v] : "role " + v;
    g.font = "bold " + Math.max(11, Math.round(0.11 * px)) + "px sans-serif"; g.textAlign = "center"; g.textBaseline = "top";
    g.lineWidth = 3; g.strokeStyle = "rgba(0,0,0,0.7)"; g.fillStyle = "#fff";
    const y = sy(truth[1]) + Math.max(8, ROBOT_R * px) + 3;
    g.strokeText(text, sx(truth[0]), y); g.fillText(text, sx(truth[0]), y);
  }

  function drawBanner(g, t) {
    let shown = null;
    for (let i = events.length - 1; i >= 0; i--) {
      const e = events[i];
      if (e.t > t) continue;
      if (t - e.t > 2500) break;
      if (e.kind === "goal" || e.kind === "shootout_kick" || e.kind === "half_time" || e.kind === "end") { shown = e; break; }
    }
    if (!shown) return;
    const text = describe(shown);
    g.font = "bold " + Math.round(0.22 * px) + "px sans-serif"; g.textAlign = "center"; g.textBaseline = "middle";
    const w = g.measureText(text).width + 0.4 * px, h = 0.4 * px, x = canvas.width / 2, y = 0.35 * px;
    g.fillStyle = "rgba(0,0,0,0.6)"; g.fillRect(x - w / 2, y - h / 2, w, h);
    g.fillStyle = "#fff"; g.fillText(text, x, y);
  }

  const stats = { robots: 0, fallen: 0, estimates: 0, extras: 0, renders: 0 };

  function render() {
    const f = frameAt(now), u = f + 1 < NF ? (now - T[f]) / (T[f + 1] - T[f]) : 0;
    const st = statusAt(now);
    ctx.drawImage(background, 0, 0);
    let nRobots = 0, nFallen = 0, nEst = 0, nExtras = 0;
    const poses = robots.map(function (r) { return sample(r.ch.pose, f, u, true); });
    robots.forEach(function (r, i) {
      const color = teamColor(r, st);
      drawExtras(ctx, r, f, poses[i], color);
      nExtras += ["landmarks", "ball_estimate", "team_ball", "role"].filter(function (n) { return r.show[n] && r.ch[n]; }).length;
    });
    robots.forEach(function (r, i) {
      const fallen = r.ch.fallen.v[f] > 0;
      drawRobot(ctx, r, poses[i], teamColor(r, st), fallen);
      nRobots++; if (fallen) nFallen++;
    });
    robots.forEach(function (r, i) {
      if (!(r.show.estimate && r.ch.estimate)) return;
      const est = sample(r.ch.estimate, f, 0, false);
      if (!Number.isFinite(est[0]) || !Number.isFinite(est[1])) return;
      drawEstimate(ctx, poses[i], est, teamColor(r, st)); nEst++;
    });
    robots.forEach(function (r, i) { drawLabel(ctx, r, f, poses[i]); });
    const b = sample(ball, f, u, true);
    ctx.fillStyle = COLORS.ball; ctx.strokeStyle = "#000"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.arc(sx(b[0]), sy(b[1]), Math.max(5, F.ball_radius * px * 1.3), 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    drawBanner(ctx, now);
    stats.robots = nRobots; stats.fallen = nFallen; stats.estimates = nEst; stats.extras = nExtras; stats.renders++;
    updateBoard(st, f, u);
    updateTimeline();
    updateToggles(f);
  }

  // ---- score board, timeline, events ------------------------------------------------------
  const shown = {};
  function setText(id, text) { if (shown[id] !== text) { shown[id] = text; document.getElementById(id).textContent = text; } }

  function updateBoard(st, f, u) {
    const stateName = MATCH.states[st.state] || String(st.state);
    setText("score", st.score[0] + " - " + st.score[1]);
    setText("pens", st.shootout || st.pens[0] || st.pens[1] ? "pens " + st.pens[0] + " - " + st.pens[1] : "");
    setText("half", st.shootout ? "shoot-out" : (st.half === 1 ? "1st half" : "2nd half"));
    let c = clock.v[f];
    if (f + 1 < NF && clock.v[f + 1] < c) c += (clock.v[f + 1] - c) * u;
    setText("clock", st.shootout ? "" : fmtClock(c));
    setText("state", stateName);
    const stateEl = document.getElementById("state");
    stateEl.style.background = STATE_COLORS[stateName] || "#30353d";
    const home = COLORS[st.home_color === "red" ? "red" : "blue"], away = COLORS[st.home_color === "red" ? "blue" : "red"];
    document.querySelector("#team-home .chip").style.background = home;
    document.querySelector("#team-away .chip").style.background = away;
    setText("time", "t " + fmtTime(now) + " / " + fmtTime(T1) + "  frame " + (f + 1) + "/" + NF);
  }

  function describe(e) {
    const sc = function (s) { return s ? " (" + s.home + "-" + s.away + ")" : ""; };
    switch (e.kind) {
      case "goal": return "GOAL " + e.team + sc(e.score);
      case "goal_disallowed": return "goal disallowed: " + e.team + ", " + (e.reason || "");
      case "ball_out": return "ball out over the " + String(e.line || "line").replace("_", " ") + (e.last_toucher ? ", last " + e.last_toucher : "");
      case "fall": return e.robot + " fell";
      case "kickoff": return "kick-off " + (e.team || "") + ", half " + e.half;
      case "half_time": return "half-time" + sc(e.score);
      case "shootout_kick": return "penalty " + e.kicker + (e.scored ? " scored" : " missed (" + e.reason + ")") + sc(e.shootout);
      case "robot_placed": return e.robot + " placed (illegal at SET)";
      case "robot_replaced": return e.robot + " replaced (" + String(e.reason || "").replace("_", " ") + ")";
      case "fault": return (e.agent || "") + " policy fault: " + (e.error || "");
      case "end": return "end: " + (e.winner ? e.winner + " wins" : "draw") + sc(e.score);
      default: return e.kind;
    }
  }

  const timeline = document.getElementById("timeline"), lanes = document.getElementById("lanes");
  const list = document.getElementById("events");
  const items = [];
  function pct(t) { return T1 > T0 ? (100 * (t - T0)) / (T1 - T0) : 0; }

  function buildTimeline() {
    const laneEls = [0, 1, 2].map(function (i) {
      const el = document.createElement("div"); el.className = "lane"; el.style.top = i * 12 + "px"; lanes.appendChild(el); return el;
    });
    const counts = {};
    events.forEach(function (e, i) {
      const spec = MARKS[e.kind];
      const b = document.createElement("button");
      b.className = "mark " + e.kind + (e.scored ? " scored" : "");
      b.dataset.kind = e.kind; b.dataset.t = String(e.t); b.dataset.index = String(i);
      b.style.left = pct(e.t) + "%"; b.style.background = spec[1];
      b.title = fmtTime(e.t) + "  " + describe(e);
      b.tabIndex = -1;
      b.addEventListener("pointerdown", function (ev) { ev.stopPropagation(); });
      b.addEventListener("click", function (ev) { ev.stopPropagation(); b.blur(); seek(e.t); });
      laneEls[spec[0]].appendChild(b);
      counts[e.kind] = (counts[e.kind] || 0) + 1;
      const li = document.createElement("li");
      li.dataset.kind = e.kind;
      li.innerHTML = '<span class="when"></span>';
      li.firstChild.textContent = fmtTime(e.t);
      li.appendChild(document.createTextNode(describe(e)));
      li.style.borderLeftColor = spec[1];
      li.addEventListener("click", function () { seek(e.t); });
      list.appendChild(li); items.push(li);
    });
    const legend = document.getElementById("legend");
    Object.keys(MARKS).forEach(function (kind) {
      if (!counts[kind]) return;
      const span = document.createElement("span");
      span.innerHTML = "<i></i>"; span.firstChild.style.background = MARKS[kind][1];
      span.appendChild(document.createTextNode(MARKS[kind][2] + " " + counts[kind]));
      legend.appendChild(span);
    });
    let scrubbing = false;
    function at(ev) { const r = timeline.getBoundingClientRect(); return T0 + ((ev.clientX - r.left) / r.width) * (T1 - T0); }
    timeline.addEventListener("pointerdown", function (ev) { scrubbing = true; timeline.setPointerCapture(ev.pointerId); seek(at(ev)); });
    timeline.addEventListener("pointermove", function (ev) { if (scrubbing) seek(at(ev)); });
    timeline.addEventListener("pointerup", function () { scrubbing = false; });
  }

  let currentEvent = -2;
  function updateTimeline() {
    const p = pct(now) + "%";
    document.getElementById("progress").style.width = p;
    document.getElementById("playhead").style.left = p;
    let lo = -1, hi = events.length - 1;
    while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (events[mid].t <= now) lo = mid; else hi = mid - 1; }
    if (lo === currentEvent) return;
    currentEvent = lo;
    items.forEach(function (li, i) { li.className = i === lo ? "current" : i < lo ? "past" : "future"; });
    const li = items[Math.max(0, lo)];
    if (li && (li.offsetTop < list.scrollTop || li.offsetTop > list.scrollTop + list.clientHeight - li.offsetHeight)) {
      list.scrollTop = li.offsetTop - list.clientHeight / 2;
    }
  }

  // ---- toggles -----------------------------------------------------------------------------
  const boxes = {}; // "robot/channel" -> checkbox
  function setShown(robotId, channel, on) {
    robots.forEach(function (r) { if ((robotId === "*" || r.id === robotId) && r.ch[channel]) r.show[channel] = !!on; });
    for (const key in boxes) { const [rid, ch] = key.split("/"); const r = robots.find(function (x) { return x.id === rid; }); boxes[key].checked = !!r.show[ch]; }
    for (const x of extras) { const all = document.getElementById("all-" + x.name); if (all) all.checked = robots.every(function (r) { return !r.ch[x.name] || r.show[x.name]; }); }
    redraw();
  }
  function buildToggles() {
    const table = document.getElementById("toggles");
    document.getElementById("no-extras").hidden = extras.some(function (x) { return x.name === "estimate"; });
    const head = document.createElement("tr");
    head.innerHTML = "<th></th>";
    extras.forEach(function (x) {
      const th = document.createElement("th"); th.title = x.title;
      const box = document.createElement("input"); box.type = "checkbox"; box.id = "all-" + x.name; box.tabIndex = -1;
      box.addEventListener("change", function () { setShown("*", x.name, box.checked); box.blur(); });
      th.appendChild(document.createTextNode(x.label)); th.appendChild(document.createElement("br")); th.appendChild(box);
      head.appendChild(th);
    });
    table.appendChild(head);
    robots.forEach(function (r) {
      const tr = document.createElement("tr"); tr.dataset.robot = r.id;
      const td = document.createElement("td"); td.className = "robot";
      td.innerHTML = '<span class="chip"></span>'; td.appendChild(document.createTextNode(r.id));
      tr.appendChild(td);
      extras.forEach(function (x) {
        const cell = document.createElement("td");
        if (r.ch[x.name]) {
          const box = document.createElement("input"); box.type = "checkbox"; box.tabIndex = -1;
          box.className = "toggle"; box.dataset.robot = r.id; box.dataset.channel = x.name; box.title = r.id + ": " + x.title;
          box.addEventListener("change", function () { setShown(r.id, x.name, box.checked); box.blur(); });
          boxes[r.id + "/" + x.name] = box; cell.appendChild(box);
        }
        tr.appendChild(cell);
      });
      table.appendChild(tr);
    });
  }
  function updateToggles(f) {
    const st = statusAt(now);
    document.querySelectorAll("#toggles tr[data-robot]").forEach(function (tr, i) {
      const r = robots[i];
      tr.querySelector(".chip").style.background = teamColor(r, st);
      const fallen = r.ch.fallen.v[f] > 0;
      if (tr.classList.contains("fallen") !== fallen) tr.classList.toggle("fallen", fallen);
    });
  }

  // ---- controls and the loop -----------------------------------------------------------------
  function buildControls() {
    const select = document.getElementById("speed");
    SPEEDS.forEach(function (s) { const o = document.createElement("option"); o.value = String(s); o.textContent = s + "x"; select.appendChild(o); });
    select.value = "1";
    select.addEventListener("change", function () { speed = Number(select.value); select.blur(); });
    const click = function (id, fn) { const b = document.getElementById(id); b.addEventListener("click", function () { fn(); b.blur(); }); };
    click("play", function () { setPlaying(!playing); });
    click("back", function () { stepFrame(-1); });
    click("forward", function () { stepFrame(1); });
    document.addEventListener("keydown", function (e) {
      if (e.target && e.target.tagName === "SELECT") return;
      const i = SPEEDS.indexOf(speed);
      switch (e.key) {
        case " ": setPlaying(!playing); break;
        case "ArrowRight": if (e.shiftKey) seek(now + 5000); else stepFrame(1); break;
        case "ArrowLeft": if (e.shiftKey) seek(now - 5000); else stepFrame(-1); break;
        case "ArrowUp": setSpeed(SPEEDS[Math.min(SPEEDS.length - 1, i + 1)]); break;
        case "ArrowDown": setSpeed(SPEEDS[Math.max(0, i - 1)]); break;
        case "Home": seek(T0); break;
        case "End": seek(T1); break;
        case "]": { const next = events.find(function (ev) { return ev.t > now + 0.5; }); if (next) seek(next.t); break; }
        case "[": { const prev = events.filter(function (ev) { return ev.t < now - 0.5; }).pop(); if (prev) seek(prev.t); break; }
        default: return;
      }
      e.preventDefault();
    });
    window.addEventListener("resize", resize);
  }

  function tick(ms) {
    if (playing) {
      if (lastTick !== null) {
        now += Math.min(250, ms - lastTick) * speed;
        if (now >= T1) { now = T1; setPlaying(false); }
        dirty = true;
      }
      lastTick = ms;
    }
    if (dirty) { dirty = false; render(); }
    requestAnimationFrame(tick);
  }

  // The match's settings (who played, seed, referee, versions...), as text: nothing of them is markup.
  function buildSettings() {
    const table = document.getElementById("settings");
    const rows = DATA.settings || [];
    document.getElementById("settings-panel").hidden = rows.length === 0;
    rows.forEach(function (row) {
      const tr = document.createElement("tr");
      const th = document.createElement("th"); th.textContent = row[0];
      const td = document.createElement("td"); td.textContent = row[1];
      tr.appendChild(th); tr.appendChild(td); table.appendChild(tr);
    });
  }

  const summary = MATCH.summary || {};
  document.getElementById("title").textContent = DATA.title + (summary.winner ? "  (winner: " + summary.winner + ")" : "");
  buildSettings();
  buildControls();
  buildToggles();
  buildTimeline();
  resize();
  redraw();

  // For tests and the curious: the state of the player, and a few handles.
  window.replay = {
    ready: true,
    readyMs: performance.now(),
    data: DATA,
    stats: stats,
    time: function () { return now; },
    frame: function () { return frameAt(now); },
    seek: seek,
    play: function () { setPlaying(true); },
    pause: function () { setPlaying(false); },
    playing: function () { return playing; },
    speed: function () { return speed; },
    setShown: setShown,
    status: function () { return statusAt(now); },
  };
  requestAnimationFrame(tick);
})();
