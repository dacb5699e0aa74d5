// The web view's shapes as plain geometry, in metres: body-frame polygons (x forwards, y left,
// from a robot's pose) and their map-frame corners. robots.js draws them; tests/web/shapes_test.js
// checks them under node.
'use strict';

(() => {
  // An EPAL pallet as a stacker docks to it [Stacker thesis, section 4.1.3]: 1.2 m along its
  // entry axis (the pose's yaw), 0.8 m across.
  const EPAL = { depth: 1.2, width: 0.8 };

  // Body-frame points [bx, by] placed at the pose (x, y, yaw): map-frame [x, y] corners.
  function placed(x, y, yaw, points) {
    const c = Math.cos(yaw), s = Math.sin(yaw);
    return points.map(([bx, by]) => [x + c * bx - s * by, y + s * bx + c * by]);
  }

  // A length x width rectangle centred on the pose, its length along the yaw, counter-clockwise.
  function rectangle(x, y, yaw, length, width) {
    const l = length / 2, w = width / 2;
    return placed(x, y, yaw, [[l, w], [-l, w], [-l, -w], [l, -w]]);
  }

  // The part of a polygon at or ahead of body x = x0: one Sutherland-Hodgman pass, exact for
  // any polygon that the line crosses at most twice, as a footprint is.
  function clipAhead(polygon, x0) {
    const out = [];
    for (let i = 0; i < polygon.length; i++) {
      const a = polygon[i], b = polygon[(i + 1) % polygon.length];
      const aIn = a[0] >= x0, bIn = b[0] >= x0;
      if (aIn) out.push(a);
      if (aIn !== bIn) out.push([x0, a[1] + ((x0 - a[0]) / (b[0] - a[0])) * (b[1] - a[1])]);
    }
    return out;
  }

  // What a robot's body is drawn of, body frame: its fleet's footprint polygon and, for a robot
  // with forks (GET /api/site gives a stacker's tines), the chassis (the footprint ahead of the
  // forks' root), the tines and their root's x. `spec` is the robot's entry of the site's robots.
  function bodyParts(spec, length, width) {
    const footprint = spec && spec.poly ? spec.poly : rectangle(0, 0, 0, length, width);
    if (!spec || !spec.forks || spec.forks.length === 0) return { footprint, chassis: footprint, forks: [], root: null };
    const root = Math.max(...spec.forks.flat().map(([x]) => x));
    return { footprint, chassis: clipAhead(footprint, root), forks: spec.forks, root };
  }

  // The centre of a pallet carried on forks whose root is at body x `root`: along the tines, its
  // entry face at their root.
  function palletOnForks(root) {
    return [root - EPAL.depth / 2, 0];
  }

  // The pallet a robot's cameras detect, at its pose [x, y, yaw] (centre, entry-axis yaw): its
  // outline and its entry face, the side the forks go in, map frame.
  function detectedPallet([x, y, yaw]) {
    const d = EPAL.depth / 2, w = EPAL.width / 2;
    return { outline: rectangle(x, y, yaw, EPAL.depth, EPAL.width), face: placed(x, y, yaw, [[d, w], [d, -w]]) };
  }

  // Who waits for whom in traffic: for every robot whose grant is WAITING, one segment from it to
  // each robot it waits for that is on the view, stopping short of both bodies' centres by
  // `inset` metres so the arrow sits between them. `robots` is a list of [id, robot] pairs as
  // GET /api/state gives them.
  function waitArrows(robots, inset = 0.0) {
    const where = new Map(robots.map(([id, r]) => [id, r]));
    const arrows = [];
    for (const [id, r] of robots) {
      if (!r.traffic || r.traffic.status !== 'WAITING' || r.health === 'lost') continue;
      for (const other of r.traffic.waiting_for || []) {
        const o = where.get(other);
        if (!o || other === id) continue;
        const dx = o.x - r.x, dy = o.y - r.y, d = Math.hypot(dx, dy);
        const k = d > 2 * inset ? inset / d : 0;
        arrows.push({ from: id, to: other, a: [r.x + k * dx, r.y + k * dy], b: [o.x - k * dx, o.y - k * dy] });
      }
    }
    return arrows;
  }

  // The mean of a polygon's corners, {x, y}.
  function centroid(polygon) {
    let x = 0, y = 0;
    for (const [px, py] of polygon) { x += px; y += py; }
    return { x: x / polygon.length, y: y / polygon.length };
  }

  // Whether point p ({x, y}) lies inside the polygon (even-odd rule).
  function inside(polygon, p) {
    let hit = false;
    for (let i = 0, j = polygon.length - 1; i < polygon.length; j = i++) {
      const [xi, yi] = polygon[i], [xj, yj] = polygon[j];
      if ((yi > p.y) !== (yj > p.y) && p.x < ((xj - xi) * (p.y - yi)) / (yj - yi) + xi) hit = !hit;
    }
    return hit;
  }

  const api = {
    EPAL, placed, rectangle, clipAhead, bodyParts, palletOnForks, detectedPallet, waitArrows, centroid, inside,
  };
  if (typeof module !== 'undefined' && module.exports) module.exports = api;
  else globalThis.fleetShapes = api;
})();
