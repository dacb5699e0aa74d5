// The web view's tables and legend: the figures line, a row per robot that reported and per
// order (with the packing chain's links), and what each colour means. app.js calls update() with
// every frame it draws and legend() once the site is known.
'use strict';

globalThis.fleetTables = (() => {
  const { STATE_COLOURS, LOST_COLOUR, GLOBAL_PLAN, RESERVATION, LOCAL_PLAN, LOCAL_PLAN_LENGTH, FLEET_COLOURS,
    DOCKING_TARGET, DETECTED_PALLET } = globalThis.fleetRobots;
  const { fmtAge, esc } = globalThis.fleetText;
  const el = (id) => document.getElementById(id);
  const OPEN = new Set(['QUEUED', 'ASSIGNED', 'ACTIVE']);

  function update(frame, site, colourOf) {
    const g = frame.globals;
    el('time-scale').textContent = g.time_scale !== undefined ? `×${g.time_scale}` : '–';
    el('orders-per-hour').textContent = g.orders_per_hour !== undefined ? g.orders_per_hour.toFixed(1) : '–';
    el('order-p95').textContent = g.orders_done ? fmtAge(g.order_time_p95_s) : '–';
    el('orders-done').textContent = g.orders_done ?? '–';
    el('orders-failed').textContent = g.orders_failed ?? '–';
    // A standby's view is read-only: it shows what it mirrors and the active server takes requests.
    const role = el('server-role');
    role.hidden = !g.standby;
    if (g.standby) {
      role.textContent = g.active_server ? `standby of ${g.active_server}: read-only` : 'standby: read-only';
    }
    const auto = el('auto-orders');
    if (document.activeElement !== auto) auto.checked = !!g.auto_orders;

    const rows = [];
    const known = new Set();
    // Configured robots that never reported are left out: a 4-robot demo of a 12-robot
    // configuration shows four rows, and the orders stay in view.
    for (const spec of site.robots) {
      known.add(spec.id);
      if (frame.robots[spec.id]) rows.push([spec.id, frame.robots[spec.id]]);
    }
    const extra = Object.keys(frame.robots).filter((id) => !known.has(id));
    extra.sort((a, b) => a.localeCompare(b, undefined, { numeric: true }));
    for (const id of extra) rows.push([id, frame.robots[id]]);
    const makerOf = Object.fromEntries(site.robots.filter((s) => s.vda5050).map((s) => [s.id, s.vda5050]));
    el('robots').tBodies[0].innerHTML = rows.map(([id, r]) => {
      if (!r) return `<tr class="lost"><td>${esc(id)}</td><td colspan="4">not seen yet</td></tr>`;
      const paused = r.state === 'PAUSED';
      const health = r.health === 'alive' ? 'alive' : `${r.health} ${fmtAge(r.age)}`;
      const detail = r.detail ? `<span class="detail">${esc(r.detail)}</span>` : '';
      const mapNote = r.map && r.map !== site.site ? `<span class="detail">map ${esc(r.map)}</span>` : '';
      const maker = makerOf[id] ? `<span class="detail" title="driven over VDA 5050">VDA 5050 ${esc(makerOf[id])}</span>` : '';
      return `<tr class="${r.health === 'lost' ? 'lost' : ''}" data-robot="${esc(id)}">` +
        `<td><span class="dot" data-colour="${esc(colourOf(r))}"></span>${esc(id)}${maker}</td>` +
        `<td>${esc(r.state)}${detail}${mapNote}</td>` +
        `<td class="health-${esc(r.health)}">${esc(health)}</td>` +
        `<td>${r.order ? esc(r.order) : ''}</td>` +
        `<td><button class="small" data-action="${paused ? 'resume' : 'pause'}" data-robot="${esc(id)}">${paused ? 'resume' : 'pause'}</button></td></tr>`;
    }).join('');
    // Colours through the CSSOM: the page's content security policy forbids inline styles.
    for (const dot of el('robots').querySelectorAll('.dot')) dot.style.background = dot.dataset.colour;

    const orders = Object.values(frame.orders);
    orders.sort((a, b) => (OPEN.has(b.state) - OPEN.has(a.state)) || (b.id - a.id));
    // The packing chain: which orders an order follows from, and which follow from it.
    const ledTo = {};
    for (const o of orders) for (const from of o.caused_by || []) (ledTo[from] = ledTo[from] || []).push(o.id);
    el('orders').tBodies[0].innerHTML = orders.map((o) => {
      const open = OPEN.has(o.state);
      const age = open ? g.sim_time - o.created : o.updated - o.created;
      const reason = o.reason && !open ? `<span class="detail">${esc(o.reason)}</span>` : '';
      const chain = (o.caused_by && o.caused_by.length ? `<span class="detail" title="${esc(o.cause)}">after ${o.caused_by.join(', ')}</span>` : '') +
        (ledTo[o.id] ? `<span class="detail">then ${ledTo[o.id].join(', ')}</span>` : '');
      return `<tr class="${open ? '' : 'ended'}" data-order="${o.id}">` +
        `<td>${o.id}${chain}</td><td>${esc(o.kind === "move" ? "move" : o.from)}</td><td>${esc(o.to)}</td><td>${esc(o.robot)}</td>` +
        `<td class="state-${esc(o.state)}">${esc(o.state)}${reason}</td><td>${esc(o.phase)}</td><td>${fmtAge(age)}</td>` +
        `<td>${open ? `<button class="small" data-action="cancel" data-order="${o.id}">cancel</button>` : ''}</td></tr>`;
    }).join('');
  }

  function legend(site) {
    const parts = Object.entries(STATE_COLOURS).map(([s, c]) => `<span><span class="dot" data-colour="${c}"></span>${s}</span>`);
    parts.push(`<span><span class="dot" data-colour="${LOST_COLOUR}"></span>lost</span>`);
    parts.push(`<span><span class="dot" data-colour="${GLOBAL_PLAN}"></span>planned path</span>`);
    parts.push(`<span><span class="dot" data-colour="${LOCAL_PLAN}"></span>local plan (next ${LOCAL_PLAN_LENGTH} m)</span>`);
    parts.push(`<span><span class="dot" data-colour="${RESERVATION}"></span>traffic reservation (hollow: waiting; dashed arrow: waits for)</span>`);
    if (site && site.robots.some((r) => r.forks)) {
      parts.push(`<span><span class="dot" data-colour="${DOCKING_TARGET}"></span>docking targets 1 and 2</span>`);
      parts.push(`<span><span class="dot" data-colour="${DETECTED_PALLET}"></span>pallet the cameras detect (dashed)</span>`);
    }
    // With several fleets each robot is outlined in its fleet's colour.
    if (site && site.fleets && site.fleets.length > 1) {
      site.fleets.forEach((f, i) => parts.push(
        `<span><span class="dot ring" data-ring="${FLEET_COLOURS[i % FLEET_COLOURS.length]}"></span>fleet ${esc(f.id)} (${esc(f.type)})</span>`));
    }
    el('legend').innerHTML = parts.join('');
    for (const ring of el('legend').querySelectorAll('.ring')) {
      ring.style.background = 'transparent';
      ring.style.border = `2px solid ${ring.dataset.ring}`;
    }
    for (const dot of el('legend').querySelectorAll('.dot:not(.ring)')) dot.style.background = dot.dataset.colour;
  }

  return { update, legend };
})();
