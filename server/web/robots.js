// The robots on the web view's canvas: planned paths, local plans, traffic reservations and waits,
// covariance ellipses, bodies (a stacker's with its forks) and the docking a stacker is in.
// app.js makes one painter over its canvas; shapes.js gives the geometry.
'use strict';

globalThis.fleetRobots = (() => {
  const shapes = globalThis.fleetShapes;
  // Task states of the thesis's state machine (plus WAITING, PAUSED, ERROR).
  const STATE_COLOURS = {
    IDLE: '#5b7083', TRACK_PATH: '#2e8b57', SEARCH_PALLET: '#e07a1f', PICK_PALLET: '#d0611a',
    DROP_PALLET: '#b5541c', GO_HOME: '#1f8a9d', WAITING: '#e0b000', PAUSED: '#8e6cc0', ERROR: '#d62828',
  };
  const LOST_COLOUR = '#a8b0b8';
  const GLOBAL_PLAN = '#1f5fd6';  // the global plan in blue [Forklift thesis, Fig. 5.12]
  const RESERVATION = 'rgba(230,120,20,0.85)';  // traffic: road places a robot holds
  const LOCAL_PLAN = '#d62828';  // the local plan in red [Forklift thesis, Fig. 5.12]
  const LOCAL_PLAN_LENGTH = 1.0;  // metres of path the robot checks against the dynamic grid (core/robot)
  const PALLET = '#9a6a3a';
  const FORKS = '#4a525a';
  const DOCKING_TARGET = '#c2185b';
  const DETECTED_PALLET = '#0077b6';
  // Each fleet's outline colour, in the order the site lists the fleets.
  const FLEET_COLOURS = ['#1d232a', '#d1495b', '#00798c', '#edae49', '#66a182'];

  // `env` is app.js's: the canvas context `ctx`, the map-to-canvas coordinates `X` and `Y`, the
  // `view` (scale, width), the `toggles`, `site()` (replaced when the map is switched), the
  // drawing helpers `label`, `polyPath`, `linePath` and `fmtAge`, and `drawn` (robot id -> where
  // it was last drawn, in CSS pixels, for tests).
  function painter(env) {
    const { ctx, X, Y, view, toggles, site, label, polyPath, linePath, fmtAge, drawn } = env;
    const specOf = (id) => site().robots.find((r) => r.id === id);

    function fleetColourOf(id) {
      const spec = specOf(id);
      const fleets = site().fleets;
      const index = spec && fleets ? fleets.findIndex((f) => f.id === spec.fleet) : 0;
      return FLEET_COLOURS[Math.max(index, 0) % FLEET_COLOURS.length];
    }

    function colourOf(r) {
      if (r.health === 'lost') return LOST_COLOUR;
      return STATE_COLOURS[r.state] || '#5b7083';
    }

    function drawPath(r) {
      if (!r.path || r.path.length < 2) return;
      ctx.strokeStyle = r.health === 'lost' ? 'rgba(160,168,176,0.6)' : GLOBAL_PLAN;
      ctx.lineWidth = 2;
      ctx.globalAlpha = 0.85;
      linePath(ctx, r.path);
      ctx.stroke();
      ctx.globalAlpha = 1;
      const [gx, gy] = r.path[r.path.length - 1];
      ctx.fillStyle = GLOBAL_PLAN;
      ctx.beginPath();
      ctx.arc(X(gx), Y(gy), 3, 0, 2 * Math.PI);
      ctx.fill();
    }

    // The local plan: the stretch of the path just ahead of the robot that it checks against the
    // other robots and what its lidar sees (the dynamic grid [Forklift thesis, section 5.3]).
    function drawLocalPlan(r) {
      if (!r.path || r.path.length < 2 || r.health === 'lost') return;
      let best = 0, bestD = Infinity;
      for (let i = 0; i + 1 < r.path.length; i++) {
        const [ax, ay] = r.path[i], [bx, by] = r.path[i + 1];
        const dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
        const t = len2 > 0 ? Math.max(0, Math.min(1, ((r.x - ax) * dx + (r.y - ay) * dy) / len2)) : 0;
        const d = Math.hypot(ax + t * dx - r.x, ay + t * dy - r.y);
        if (d < bestD) { bestD = d; best = i; }
      }
      const pts = [[r.x, r.y]];
      let left = LOCAL_PLAN_LENGTH;
      for (let i = best + 1; i < r.path.length && left > 0; i++) {
        const [px, py] = pts[pts.length - 1];
        const [nx, ny] = r.path[i];
        const d = Math.hypot(nx - px, ny - py);
        if (d >= left) { pts.push([px + (nx - px) * left / d, py + (ny - py) * left / d]); left = 0; } else { pts.push([nx, ny]); left -= d; }
      }
      if (pts.length < 2) return;
      ctx.strokeStyle = LOCAL_PLAN;
      ctx.lineWidth = 3;
      linePath(ctx, pts);
      ctx.stroke();
    }

    // Traffic reservations: the road places a robot holds, as dots along its way, hollow while it
    // waits for them to grow.
    function drawReservations(r) {
      if (!r.traffic || !r.traffic.reserved || r.health === 'lost') return;
      const waiting = r.traffic.status === 'WAITING';
      ctx.strokeStyle = RESERVATION;
      ctx.fillStyle = RESERVATION;
      ctx.lineWidth = 1.5;
      for (const [x, y] of r.traffic.reserved) {
        ctx.beginPath();
        ctx.arc(X(x), Y(y), Math.max(2, 0.03 * view.scale), 0, 2 * Math.PI);
        if (waiting) ctx.stroke(); else ctx.fill();
      }
    }

    // Who waits for whom: a dashed arrow from each waiting robot to each robot it waits for.
    function drawWaits(robots) {
      ctx.strokeStyle = RESERVATION;
      ctx.fillStyle = RESERVATION;
      ctx.lineWidth = 2;
      for (const { a, b } of shapes.waitArrows(robots, 0.12)) {
        const [ax, ay, bx, by] = [X(a[0]), Y(a[1]), X(b[0]), Y(b[1])];
        ctx.setLineDash([5, 3]);
        ctx.beginPath();
        ctx.moveTo(ax, ay);
        ctx.lineTo(bx, by);
        ctx.stroke();
        ctx.setLineDash([]);
        const angle = Math.atan2(by - ay, bx - ax), head = 7;
        ctx.beginPath();
        ctx.moveTo(bx, by);
        ctx.lineTo(bx - head * Math.cos(angle - 0.4), by - head * Math.sin(angle - 0.4));
        ctx.lineTo(bx - head * Math.cos(angle + 0.4), by - head * Math.sin(angle + 0.4));
        ctx.closePath();
        ctx.fill();
      }
    }

    // The 95 % ellipse of the position covariance [xx, xy, yy].
    function drawCovariance(r) {
      const [a, b, c] = r.cov;
      const mean = (a + c) / 2;
      const d = Math.sqrt(((a - c) / 2) ** 2 + b * b);
      const l1 = Math.max(mean + d, 0), l2 = Math.max(mean - d, 0);
      const k = 2.4477;  // sqrt(chi2(2 dof, 0.95))
      const rx = k * Math.sqrt(l1) * view.scale, ry = k * Math.sqrt(l2) * view.scale;
      if (rx < 0.5) return;
      const angle = 0.5 * Math.atan2(2 * b, a - c);
      ctx.strokeStyle = 'rgba(123,44,191,0.95)';
      ctx.fillStyle = 'rgba(123,44,191,0.18)';
      ctx.lineWidth = 1;
      ctx.beginPath();
      ctx.ellipse(X(r.x), Y(r.y), rx, Math.max(ry, 0.5), -angle, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
    }

    function drawRobot(id, r) {
      const [length, width] = r.fp;
      const lost = r.health === 'lost';
      const colour = colourOf(r);
      // The footprint polygon its fleet declares; a stacker's chassis and fork tines inside it.
      const parts = shapes.bodyParts(specOf(id), length, width);
      if (toggles.truth && r.truth) {
        const [tx, ty, tyaw] = r.truth;
        polyPath(ctx, shapes.placed(tx, ty, tyaw, parts.footprint));
        ctx.setLineDash([3, 2]);
        ctx.strokeStyle = '#222';
        ctx.lineWidth = 1.2;
        ctx.stroke();
        ctx.setLineDash([]);
      }
      const alpha = lost ? 0.55 : 1;
      const onBody = (points) => shapes.placed(r.x, r.y, r.yaw, points);
      ctx.globalAlpha = alpha;
      if (parts.forks.length) {
        // Between the tines the footprint is only what traffic keeps clear: a lighter shade.
        polyPath(ctx, onBody(parts.footprint));
        ctx.fillStyle = colour;
        ctx.globalAlpha = 0.3 * alpha;
        ctx.fill();
        ctx.globalAlpha = alpha;
        ctx.fillStyle = FORKS;
        for (const tine of parts.forks) {
          polyPath(ctx, onBody(tine));
          ctx.fill();
        }
      }
      polyPath(ctx, onBody(parts.chassis));
      ctx.fillStyle = colour;
      ctx.fill();
      if (parts.forks.length) polyPath(ctx, onBody(parts.footprint));
      ctx.lineWidth = r.health === 'stale' || (site().fleets && site().fleets.length > 1) ? 2 : 1;
      ctx.strokeStyle = r.health === 'stale' ? '#c77c02' : fleetColourOf(id);
      if (r.health === 'stale') ctx.setLineDash([3, 2]);
      ctx.stroke();
      ctx.setLineDash([]);
      if (r.carrying) {
        // On a stacker's forks an EPAL pallet; else a pallet at the front half of the body.
        const p = site().pallet_size;
        polyPath(ctx, parts.forks.length
          ? onBody(shapes.rectangle(...shapes.palletOnForks(parts.root), 0, shapes.EPAL.depth, shapes.EPAL.width))
          : onBody(shapes.rectangle(length * 0.25, 0, 0, Math.min(p, length / 2), Math.min(p, width))));
        ctx.fillStyle = PALLET;
        ctx.fill();
        ctx.strokeStyle = '#3d2b16';
        ctx.stroke();
      }
      // Heading: a triangle at the front.
      const [[ax, ay], [bx1, by1], [bx2, by2]] =
        onBody([[length / 2 + 0.03, 0], [length / 2 - 0.01, width * 0.3], [length / 2 - 0.01, -width * 0.3]]);
      ctx.fillStyle = lost ? LOST_COLOUR : '#1d232a';
      ctx.beginPath();
      ctx.moveTo(X(ax), Y(ay));
      ctx.lineTo(X(bx1), Y(by1));
      ctx.lineTo(X(bx2), Y(by2));
      ctx.closePath();
      ctx.fill();
      ctx.globalAlpha = 1;
      // Over the body: an ellipse smaller than the robot still shows.
      if (toggles.cov && r.cov && !lost) drawCovariance(r);
      const px = X(r.x), py = Y(r.y);
      drawn[id] = [px, py];
      if (toggles.labels) drawLabel(id, r, px, py, Math.max(length, width) * view.scale * 0.6 + 4);
    }

    function drawLabel(id, r, px, py, half) {
      const lost = r.health === 'lost';
      ctx.font = 'bold 12px sans-serif';
      ctx.fillStyle = lost ? '#6b7785' : '#10161c';
      label(ctx, id, px + half, py - half + 6, px - half);
      ctx.font = '11px sans-serif';
      let note = '';
      if (lost) note = `lost ${fmtAge(r.age)} ago`;
      else if (r.health === 'stale') note = `stale ${fmtAge(r.age)}`;
      else if (r.state === 'WAITING' || r.state === 'PAUSED' || r.state === 'ERROR') note = r.detail || r.state.toLowerCase();
      if (!note) return;
      const w = ctx.measureText(note).width;
      const nx = px + half + w > view.width - 2 ? px - half - w : px + half;
      ctx.fillStyle = 'rgba(255,255,255,0.85)';
      ctx.fillRect(nx - 2, py - half + 9, w + 4, 14);
      ctx.fillStyle = lost ? '#6b7785' : r.state === 'ERROR' ? '#b00' : '#7a5b00';
      ctx.fillText(note, nx, py - half + 20);
    }

    // A docking under way (a stacker's): targets 1 and 2 of its two-target approach, where the
    // rear axle is steered to before the final approach, and the pallet its cameras detect, as an
    // EPAL outline, dashed and unfilled unlike the pallets standing on their places, its entry face
    // drawn thick.
    function drawDocking(r) {
      if (r.health === 'lost') return;
      if (r.dock_targets && r.dock_targets.length) {
        ctx.strokeStyle = DOCKING_TARGET;
        ctx.fillStyle = DOCKING_TARGET;
        ctx.lineWidth = 1;
        ctx.setLineDash([2, 3]);
        linePath(ctx, r.dock_targets);
        ctx.stroke();
        ctx.setLineDash([]);
        const size = Math.max(4, 0.08 * view.scale);
        ctx.lineWidth = 2;
        ctx.font = 'bold 11px sans-serif';
        r.dock_targets.forEach(([x, y], i) => {
          const px = X(x), py = Y(y);
          ctx.beginPath();
          ctx.arc(px, py, size, 0, 2 * Math.PI);
          ctx.moveTo(px - size, py);
          ctx.lineTo(px + size, py);
          ctx.moveTo(px, py - size);
          ctx.lineTo(px, py + size);
          ctx.stroke();
          if (toggles.labels) ctx.fillText(String(i + 1), px + size + 2, py - size);
        });
      }
      if (r.detected_pallet) {
        const { outline, face } = shapes.detectedPallet(r.detected_pallet);
        polyPath(ctx, outline);
        ctx.strokeStyle = DETECTED_PALLET;
        ctx.lineWidth = 2;
        ctx.setLineDash([6, 3]);
        ctx.stroke();
        ctx.setLineDash([]);
        linePath(ctx, face);
        ctx.lineWidth = 4;
        ctx.stroke();
      }
    }

    return { colourOf, drawPath, drawLocalPlan, drawReservations, drawWaits, drawRobot, drawDocking };
  }

  return {
    STATE_COLOURS, LOST_COLOUR, GLOBAL_PLAN, RESERVATION, LOCAL_PLAN, LOCAL_PLAN_LENGTH, PALLET, FORKS, DOCKING_TARGET,
    DETECTED_PALLET, FLEET_COLOURS, painter,
  };
})();
