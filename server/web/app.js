// Fleet's live web view: the site to scale on a canvas, robots and orders from the server's
// event stream (a full frame, then diffs), and the controls of the JSON API.
'use strict';

(() => {
  const params = new URLSearchParams(location.search);
  // The token comes with the address the server logs (?token=...); kept for this tab only.
  let token = params.get('token') || sessionStorage.getItem('fleet-token') || '';
  if (params.get('token')) sessionStorage.setItem('fleet-token', token);
  // ?fps: redraw every animation frame, even without news, to measure drawing speed.
  const alwaysDraw = params.has('fps');

  // robots.js draws the robots, the loading areas share its colours; tables.js fills the tables.
  const { PALLET } = globalThis.fleetRobots;
  const tables = globalThis.fleetTables;
  const { centroid, inside } = globalThis.fleetShapes;
  const { fmtAge, esc } = globalThis.fleetText;

  const el = (id) => document.getElementById(id);
  const canvas = el('map');
  const ctx = canvas.getContext('2d');
  const staticLayer = document.createElement('canvas');
  // A label right of what it names, or left of it where it would run off the map's east edge.
  function label(c, text, x, y, leftX) {
    const w = c.measureText(text).width;
    c.fillText(text, x + w > view.width - 2 ? leftX - w : x, y);
  }

  let site = null;
  let frame = { globals: {}, robots: {}, orders: {}, obstacles: {}, pallets: {} };
  let dirty = true;
  let tablesDirty = true;
  let lastTables = 0;
  let lastEventAt = 0;
  let pickArea = null;
  const pendingObstacles = new Map();  // id -> wanted state, until the stream confirms it
  const view = { scale: 1, ox: 0, oy: 0, dpr: 1, width: 0, height: 0 };
  const toggles = { graph: false, truth: false, cov: true, paths: true, labels: true };
  const stats = { rafs: 0, draws: 0, events: 0, fullFrames: 0, diffFrames: 0 };
  const drawn = {};  // robot id -> [x, y] in CSS pixels as last drawn; read by tests

  // ---- coordinates: map frame (x right, y up, metres) <-> canvas CSS pixels ----
  const X = (x) => view.ox + (x - site.bounds.min_x) * view.scale;
  const Y = (y) => view.oy + (site.bounds.max_y - y) * view.scale;
  const toMap = (px, py) => ({
    x: (px - view.ox) / view.scale + site.bounds.min_x,
    y: site.bounds.max_y - (py - view.oy) / view.scale,
  });

  function fit() {
    const rect = canvas.getBoundingClientRect();
    view.dpr = window.devicePixelRatio || 1;
    view.width = rect.width;
    view.height = rect.height;
    canvas.width = Math.max(1, Math.round(rect.width * view.dpr));
    canvas.height = Math.max(1, Math.round(rect.height * view.dpr));
    if (!site) return;
    const b = site.bounds;
    const margin = 24;
    view.scale = Math.min((rect.width - 2 * margin) / (b.max_x - b.min_x), (rect.height - 2 * margin) / (b.max_y - b.min_y));
    view.ox = (rect.width - (b.max_x - b.min_x) * view.scale) / 2;
    view.oy = (rect.height - (b.max_y - b.min_y) * view.scale) / 2;
    drawStatic();
    dirty = true;
  }

  function polyPath(c, points) {
    c.beginPath();
    points.forEach(([x, y], i) => (i ? c.lineTo(X(x), Y(y)) : c.moveTo(X(x), Y(y))));
    c.closePath();
  }

  function linePath(c, points) {
    c.beginPath();
    points.forEach(([x, y], i) => (i ? c.lineTo(X(x), Y(y)) : c.moveTo(X(x), Y(y))));
  }

  const robotsLayer = globalThis.fleetRobots.painter({
    ctx, X, Y, view, toggles, site: () => site, label, polyPath, linePath, fmtAge, drawn,
  });

  // Roads, graph, racks, anchors and homes never change: drawn once per size into a layer.
  function drawStatic() {
    staticLayer.width = canvas.width;
    staticLayer.height = canvas.height;
    const c = staticLayer.getContext('2d');
    c.setTransform(view.dpr, 0, 0, view.dpr, 0, 0);
    c.fillStyle = '#dde1e5';
    c.fillRect(0, 0, view.width, view.height);
    const b = site.bounds;
    c.fillStyle = '#f4f1e8';
    c.strokeStyle = '#555';
    c.lineWidth = 1.5;
    c.fillRect(X(b.min_x), Y(b.max_y), (b.max_x - b.min_x) * view.scale, (b.max_y - b.min_y) * view.scale);
    c.strokeRect(X(b.min_x), Y(b.max_y), (b.max_x - b.min_x) * view.scale, (b.max_y - b.min_y) * view.scale);

    for (const lane of site.lanes) {
      const colour = lane.drivable ? '#8d8d8d' : '#cfcfcf';
      c.fillStyle = colour;
      c.strokeStyle = colour;  // a hairline of the same colour closes seams between pieces
      c.lineWidth = 0.8;
      polyPath(c, lane.outline);
      c.fill();
      c.stroke();
    }
    c.strokeStyle = 'rgba(255,255,255,0.8)';
    c.lineWidth = 1;
    c.setLineDash([4, 4]);
    for (const ref of site.references) {
      linePath(c, ref.points);
      c.stroke();
    }
    c.setLineDash([]);

    if (toggles.graph) {
      const pts = site.graph.points;
      c.strokeStyle = 'rgba(32,96,192,0.55)';
      c.lineWidth = 1;
      c.beginPath();
      for (const [i, j] of site.graph.edges) {
        c.moveTo(X(pts[i][0]), Y(pts[i][1]));
        c.lineTo(X(pts[j][0]), Y(pts[j][1]));
      }
      c.stroke();
      c.fillStyle = '#2060c0';
      for (const [x, y] of pts) c.fillRect(X(x) - 1.5, Y(y) - 1.5, 3, 3);
    }

    c.font = '11px sans-serif';
    for (const rack of site.racks) {
      c.fillStyle = '#b9a98a';
      c.strokeStyle = '#6b5b3e';
      polyPath(c, rack.polygon);
      c.fill();
      c.stroke();
    }
    for (const h of site.homes) {
      const s = Math.max(4, 0.05 * view.scale);
      c.strokeStyle = '#4a6fa5';
      c.lineWidth = 1.2;
      c.strokeRect(X(h.x) - s, Y(h.y) - s, 2 * s, 2 * s);
      c.fillStyle = '#4a6fa5';
      label(c, h.id, X(h.x) + s + 2, Y(h.y) + s, X(h.x) - s - 2);
    }
    for (const a of site.anchors) {
      const px = X(a.x), py = Y(a.y);
      c.fillStyle = '#7b2cbf';
      c.beginPath();
      c.moveTo(px, py - 7);
      c.lineTo(px + 6, py + 5);
      c.lineTo(px - 6, py + 5);
      c.closePath();
      c.fill();
      label(c, a.id, px + 8, py + 4, px - 8);
    }
  }

  // ---- the dynamic layer ----
  function areaHasPallet(area) {
    const p = frame.pallets[area.id];
    return p === undefined ? area.pallet_at_start : p;
  }

  function drawAreas() {
    const size = site.pallet_size * view.scale;
    ctx.font = '11px sans-serif';
    for (const a of site.areas) {
      const px = X(a.x), py = Y(a.y);
      ctx.save();
      ctx.translate(px, py);
      ctx.rotate(-a.yaw);
      const has = areaHasPallet(a);
      ctx.lineWidth = 1.5;
      ctx.strokeStyle = '#6b4a26';
      ctx.setLineDash(has ? [] : [3, 3]);
      if (has) {
        ctx.fillStyle = PALLET;
        ctx.fillRect(-size / 2, -size / 2, size, size);
      }
      ctx.strokeRect(-size / 2, -size / 2, size, size);
      ctx.setLineDash([]);
      // The side a forklift approaches from.
      ctx.beginPath();
      ctx.moveTo(size / 2 + 2, 0);
      ctx.lineTo(size / 2 + 8, 0);
      ctx.stroke();
      ctx.restore();
      if (pickArea === a.id) {
        ctx.strokeStyle = '#1f5fd6';
        ctx.lineWidth = 3;
        ctx.beginPath();
        ctx.arc(px, py, size * 0.9 + 4, 0, 2 * Math.PI);
        ctx.stroke();
      }
      ctx.fillStyle = '#3d2b16';
      label(ctx, a.id, px + size / 2 + 3, py - size / 2 - 2, px - size / 2 - 3);
    }
  }

  function drawObstacles() {
    for (const o of site.obstacles) {
      const enabled = frame.obstacles[o.id] ?? o.enabled_at_start;
      const pending = pendingObstacles.has(o.id);
      polyPath(ctx, o.polygon);
      ctx.lineWidth = 2;
      if (enabled) {
        ctx.fillStyle = 'rgba(214,40,40,0.75)';
        ctx.fill();
        ctx.strokeStyle = '#8b1a1a';
      } else {
        ctx.fillStyle = 'rgba(214,40,40,0.08)';
        ctx.fill();
        ctx.strokeStyle = '#d62828';
        ctx.setLineDash([5, 4]);
      }
      if (pending) ctx.strokeStyle = '#1f5fd6';
      ctx.stroke();
      ctx.setLineDash([]);
      if (toggles.labels) {
        const c = centroid(o.polygon);
        ctx.fillStyle = enabled ? '#fff' : '#8b1a1a';
        ctx.font = '10px sans-serif';
        ctx.textAlign = 'center';
        ctx.fillText(o.id, X(c.x), Y(c.y) + 3);
        ctx.textAlign = 'left';
      }
    }
  }

  function draw() {
    if (!site) return;
    stats.draws++;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.drawImage(staticLayer, 0, 0);
    ctx.setTransform(view.dpr, 0, 0, view.dpr, 0, 0);
    drawObstacles();
    drawAreas();
    const robots = Object.entries(frame.robots);
    // Lost robots under the live ones, paths under every body.
    robots.sort(([, a], [, b]) => (a.health === 'lost') - (b.health === 'lost'));
    if (toggles.paths) for (const [, r] of robots) robotsLayer.drawPath(r);
    if (toggles.paths) for (const [, r] of robots) robotsLayer.drawLocalPlan(r);
    if (toggles.paths) for (const [, r] of robots) robotsLayer.drawReservations(r);
    if (toggles.paths) robotsLayer.drawWaits(robots);
    for (let i = robots.length - 1; i >= 0; i--) robotsLayer.drawRobot(robots[i][0], robots[i][1]);
    // Over the bodies: a stacker docking passes over its targets and forks into the pallet.
    for (const [, r] of robots) robotsLayer.drawDocking(r);
  }

  // ---- API ----
  function toast(text, error) {
    const t = document.createElement('div');
    t.className = 'toast' + (error ? ' error' : '');
    t.textContent = text;
    el('toasts').appendChild(t);
    setTimeout(() => t.remove(), error ? 6000 : 2500);
    while (el('toasts').children.length > 4) el('toasts').firstChild.remove();
  }

  async function api(method, path, body) {
    if (!token) {
      el('token-box').hidden = false;
      toast('set the API token first (the server logs it)', true);
      throw new Error('no token');
    }
    const res = await fetch(path, {
      method,
      headers: { 'Content-Type': 'application/json', Authorization: `Bearer ${token}` },
      body: body === undefined ? undefined : JSON.stringify(body),
    });
    let data = {};
    try { data = await res.json(); } catch (e) { /* an empty body */ }
    if (!res.ok) {
      if (res.status === 401 || res.status === 403) el('token-box').hidden = false;
      toast(data.error || `${res.status} ${res.statusText}`, true);
      throw new Error(data.error || res.statusText);
    }
    return data;
  }

  // Reading needs the viewer's token or the operator's; the server logs both.
  async function read(path) {
    const res = await fetch(path, { headers: token ? { Authorization: `Bearer ${token}` } : {} });
    if (res.status === 401 || res.status === 403) {
      el('token-box').hidden = false;
      throw new Error("the viewer's or the operator's token is needed (the server logs both)");
    }
    return res.json();
  }

  function setHint(text) {
    el('hint').textContent = text;
    el('hint').classList.toggle('on', !!text);
  }

  function areaAt(p) {
    // Generous in screen terms: pallets are small at table scale.
    const reach = Math.max(site.pallet_size * 0.8, 10 / view.scale);
    let best = null, bestD = reach;
    for (const a of site.areas) {
      const d = Math.hypot(a.x - p.x, a.y - p.y);
      if (d < bestD) { best = a; bestD = d; }
    }
    return best;
  }

  async function onCanvasClick(ev) {
    if (!site) return;
    const rect = canvas.getBoundingClientRect();
    const p = toMap(ev.clientX - rect.left, ev.clientY - rect.top);
    const area = areaAt(p);
    if (area) return onAreaClick(area);
    const obstacle = site.obstacles.find((o) => inside(o.polygon, p));
    if (obstacle) {
      const enabled = !(frame.obstacles[obstacle.id] ?? obstacle.enabled_at_start);
      pendingObstacles.set(obstacle.id, enabled);
      dirty = true;
      try {
        await api('POST', `/api/obstacles/${encodeURIComponent(obstacle.id)}`, { enabled });
        toast(`obstacle ${obstacle.id} ${enabled ? 'on' : 'off'}`);
      } catch (e) {
        pendingObstacles.delete(obstacle.id);
      }
      dirty = true;
      return;
    }
    if (pickArea) { pickArea = null; setHint(''); dirty = true; }
  }

  async function onAreaClick(area) {
    if (!pickArea) {
      if (!areaHasPallet(area)) toast(`${area.id} holds no pallet now; the order may still be queued behind one`);
      pickArea = area.id;
      setHint(`pick at ${area.id}: now click the drop area (Esc cancels)`);
      dirty = true;
      return;
    }
    if (pickArea === area.id) { pickArea = null; setHint(''); dirty = true; return; }
    const from = pickArea;
    pickArea = null;
    setHint('');
    dirty = true;
    try {
      const r = await api('POST', '/api/orders', { from, to: area.id });
      toast(`order ${r.order_id}: ${from} → ${area.id}`);
    } catch (e) { /* shown by api() */ }
  }

  // ---- the stream ----
  // Paths travel apart from the robots' other fields, only when a robot's path changed.
  function takePaths(paths) {
    for (const [id, path] of Object.entries(paths || {}))
      if (frame.robots[id]) frame.robots[id].path = path;
  }

  function applyDiff(d) {
    for (const name of ['robots', 'orders']) {
      const section = frame[name];
      for (const [id, fields] of Object.entries(d[name] || {})) {
        const entity = section[id] || (section[id] = {});
        for (const [k, v] of Object.entries(fields)) {
          if (v === null) delete entity[k]; else entity[k] = v;
        }
      }
      for (const id of d[`${name}_removed`] || []) delete section[id];
    }
    for (const name of ['obstacles', 'pallets', 'globals']) {
      Object.assign(frame[name], d[name] || {});
      for (const k of d[`${name}_removed`] || []) delete frame[name][k];
    }
    takePaths(d.paths);
  }

  // The server switched its robots to another map of the site: draw that map's roads.
  let reloadingSite = false;
  async function reloadSite() {
    if (reloadingSite) return;
    reloadingSite = true;
    try {
      site = await read('/api/site');
      el('site-name').textContent = `site ${site.site}`;
      el('map-select').innerHTML = site.maps.map((m) => `<option${m === site.site ? ' selected' : ''}>${esc(m)}</option>`).join('');
      fit();
      toast(`map ${site.site}`);
    } finally {
      reloadingSite = false;
    }
  }

  function onFrame() {
    if (frame.globals.map && site && frame.globals.map !== site.site) reloadSite();
    for (const [id, wanted] of pendingObstacles) if (frame.obstacles[id] === wanted) pendingObstacles.delete(id);
    lastEventAt = performance.now();
    stats.events++;
    dirty = true;
    tablesDirty = true;
  }

  function connect() {
    // EventSource cannot send headers: the token goes in the query.
    const source = new EventSource(`/api/stream?token=${encodeURIComponent(token)}`);
    const status = el('connection');
    source.addEventListener('full', (e) => {
      frame = JSON.parse(e.data);
      takePaths(frame.paths);
      delete frame.paths;
      stats.fullFrames++;
      onFrame();
    });
    source.addEventListener('diff', (e) => {
      applyDiff(JSON.parse(e.data));
      stats.diffFrames++;
      onFrame();
    });
    source.onopen = () => { status.textContent = 'live'; status.className = 'badge live'; };
    // EventSource reconnects by itself; the server then starts again with a full frame.
    source.onerror = () => { status.textContent = 'reconnecting'; status.className = 'badge down'; };
  }

  // ---- the loop ----
  let fpsCount = 0, fpsSince = performance.now();
  function tick(now) {
    stats.rafs++;
    fpsCount++;
    if (now - fpsSince >= 1000) {
      el('fps').textContent = `${Math.round((fpsCount * 1000) / (now - fpsSince))} fps`;
      fpsCount = 0;
      fpsSince = now;
    }
    if (lastEventAt && now - lastEventAt > 2000) {
      const status = el('connection');
      if (status.textContent === 'live') { status.textContent = 'no news'; status.className = 'badge down'; }
    } else if (lastEventAt && el('connection').textContent === 'no news') {
      el('connection').textContent = 'live';
      el('connection').className = 'badge live';
    }
    if (dirty || alwaysDraw) {
      dirty = false;
      draw();
    }
    // The tables are DOM work: at most four times a second.
    if (tablesDirty && now - lastTables > 250 && site) {
      tablesDirty = false;
      lastTables = now;
      tables.update(frame, site, robotsLayer.colourOf);
    }
    requestAnimationFrame(tick);
  }

  function bindControls() {
    canvas.addEventListener('click', onCanvasClick);
    document.addEventListener('keydown', (e) => {
      if (e.key === 'Escape' && pickArea) { pickArea = null; setHint(''); dirty = true; }
    });
    for (const [id, key] of [['show-graph', 'graph'], ['show-truth', 'truth'], ['show-cov', 'cov'], ['show-paths', 'paths'], ['show-labels', 'labels']]) {
      const box = el(id);
      toggles[key] = box.checked;
      box.addEventListener('change', () => {
        toggles[key] = box.checked;
        if (key === 'graph') drawStatic();
        dirty = true;
      });
    }
    el('auto-orders').addEventListener('change', async (e) => {
      const enabled = e.target.checked;
      try {
        await api('POST', '/api/auto-orders', { enabled });
        toast(`automatic orders ${enabled ? 'on' : 'off'}`);
      } catch (err) { e.target.checked = !enabled; }
    });
    el('map-switch').addEventListener('click', async () => {
      const map = el('map-select').value;
      const robot = el('map-robot').value;
      try {
        await api('POST', '/api/map', robot ? { map, robot } : { map });
        toast(`map ${map} for ${robot || 'every robot'}`);
      } catch (e) { /* shown by api() */ }
    });
    el('robots').addEventListener('click', async (e) => {
      const b = e.target.closest('button[data-action]');
      if (!b) return;
      try {
        await api('POST', `/api/robots/${encodeURIComponent(b.dataset.robot)}/${b.dataset.action}`);
        toast(`${b.dataset.robot} ${b.dataset.action}d`);
      } catch (err) { /* shown by api() */ }
    });
    el('orders').addEventListener('click', async (e) => {
      const b = e.target.closest('button[data-action="cancel"]');
      if (!b) return;
      try {
        await api('DELETE', `/api/orders/${b.dataset.order}`);
        toast(`order ${b.dataset.order} cancelled`);
      } catch (err) { /* shown by api() */ }
    });
    new ResizeObserver(fit).observe(canvas);
  }

  let started = false;
  async function start() {
    site = await read('/api/site');
    started = true;
    el('site-name').textContent = `site ${site.site}`;
    document.title = `Fleet – ${site.site}`;
    el('map-select').innerHTML = site.maps.map((m) => `<option${m === site.site ? ' selected' : ''}>${esc(m)}</option>`).join('');
    el('map-robot').innerHTML = '<option value="">all robots</option>' + site.robots.map((r) => `<option>${esc(r.id)}</option>`).join('');
    tables.legend(site);
    bindControls();
    fit();
    connect();
    requestAnimationFrame(tick);
  }

  // For tests and benchmarks: where things are drawn, and how often the page drew.
  window.fleetView = {
    stats,
    drawn,
    get site() { return site; },
    get frame() { return frame; },
    toScreen(x, y) { return [X(x), Y(y)]; },
  };

  el('token-set').addEventListener('click', () => {
    token = el('token-input').value.trim();
    sessionStorage.setItem('fleet-token', token);
    el('token-box').hidden = !!token;
    if (!started) start().catch((e) => toast(`cannot load the site: ${e.message}`, true));
  });
  if (!token) el('token-box').hidden = false;
  start().catch((e) => toast(`cannot load the site: ${e.message}`, true));
})();
