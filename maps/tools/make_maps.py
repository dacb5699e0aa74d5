#!/usr/bin/env python3
"""Writes the shipped site maps: maps/{table_a,table_b,warehouse,big_warehouse,mid_warehouse,plant}.{xodr,yaml}.

A map is drawn as straight road segments between nodes. Every road is one lane of the site's
road width, with its lane centre on the reference line (laneOffset = half the width), driven both
ways. Where two segments meet, a corner road (quarter arc or straight piece) links them; where
three or four meet, a junction holds one connecting road for every pair of arms. Turn radius is
half the road width, so a junction covers exactly the crossing of the two strips.

The plant, a real-scale site with two-lane roads, is drawn by plant.py.

Usage: maps/tools/make_maps.py [OUTPUT_DIR]   (default: the maps/ folder beside this script)
"""

import math
import os
import sys

from lane_network import corner
from plant import plant


def fmt(v):
    return f"{v:.6f}".rstrip("0").rstrip(".") if v != 0 else "0"


class Network:
    def __init__(self, name, road_width):
        self.name = name
        self.hw = road_width / 2.0
        self.nodes = {}
        self.edges = []  # (u, v, name)
        self.roads = []  # dicts
        self.junctions = []

    def node(self, name, x, y):
        self.nodes[name] = (x, y)

    def edge(self, u, v, name=""):
        self.edges.append((u, v, name))

    def build(self):
        r = self.hw
        arms = {n: [] for n in self.nodes}
        for i, (u, v, _) in enumerate(self.edges):
            (ux, uy), (vx, vy) = self.nodes[u], self.nodes[v]
            length = math.hypot(vx - ux, vy - uy)
            d = ((vx - ux) / length, (vy - uy) / length)
            arms[u].append((i, d, "start"))
            arms[v].append((i, (-d[0], -d[1]), "end"))
        # Edge roads, trimmed where they enter a corner or junction.
        edge_road = {}
        for i, (u, v, name) in enumerate(self.edges):
            (ux, uy), (vx, vy) = self.nodes[u], self.nodes[v]
            length = math.hypot(vx - ux, vy - uy)
            d = ((vx - ux) / length, (vy - uy) / length)
            t0 = r if len(arms[u]) >= 2 else 0.0
            t1 = r if len(arms[v]) >= 2 else 0.0
            if length - t0 - t1 <= 1e-6:
                raise SystemExit(f"{self.name}: edge {u}-{v} is too short for its junctions")
            road = {
                "id": str(i + 1), "name": name or f"{u}-{v}", "junction": "-1",
                "x": ux + t0 * d[0], "y": uy + t0 * d[1], "hdg": math.atan2(d[1], d[0]),
                "length": length - t0 - t1, "curvature": 0.0, "pred": None, "succ": None,
            }
            edge_road[i] = road
            self.roads.append(road)
        next_id = 1000
        for n, node_arms in arms.items():
            if len(node_arms) < 2:
                continue
            px, py = self.nodes[n]
            junction = None
            if len(node_arms) >= 3:
                junction = {"id": str(len(self.junctions) + 1), "name": n, "connections": []}
                self.junctions.append(junction)
            pairs = [(a, b) for ai, a in enumerate(node_arms) for b in node_arms[ai + 1:]]
            for a, b in pairs:
                ia, da, ea = a
                ib, db, eb = b
                h1, length, curvature = corner(self.name, n, da, db, r)
                road = {
                    "id": str(next_id), "name": f"{n} {edge_road[ia]['name']} / {edge_road[ib]['name']}",
                    "junction": junction["id"] if junction else "-1",
                    "x": px + r * da[0], "y": py + r * da[1], "hdg": h1, "length": length,
                    "curvature": curvature,
                    "pred": ("road", edge_road[ia]["id"], ea), "succ": ("road", edge_road[ib]["id"], eb),
                }
                next_id += 1
                self.roads.append(road)
                if junction:
                    junction["connections"].append((edge_road[ia]["id"], road["id"], "start"))
                    junction["connections"].append((edge_road[ib]["id"], road["id"], "end"))
                else:
                    for arm, contact in ((a, "start"), (b, "end")):
                        key = "pred" if arm[2] == "start" else "succ"
                        edge_road[arm[0]][key] = ("road", road["id"], contact)
            if junction:
                for i, _, end in node_arms:
                    edge_road[i]["pred" if end == "start" else "succ"] = ("junction", junction["id"], None)

    def xodr(self):
        out = ['<?xml version="1.0" encoding="UTF-8"?>', "<OpenDRIVE>",
               f'  <header revMajor="1" revMinor="6" name="{self.name}" version="1" '
               'date="2026-11-21" north="0" south="0" east="0" west="0"/>']
        w = fmt(2 * self.hw)
        for rd in self.roads:
            out.append(f'  <road name="{rd["name"]}" length="{fmt(rd["length"])}" id="{rd["id"]}" '
                       f'junction="{rd["junction"]}" rule="RHT">')
            out.append("    <link>")
            lane_link = []
            for key, tag in (("pred", "predecessor"), ("succ", "successor")):
                link = rd[key]
                if not link:
                    continue
                kind, target, contact = link
                cp = f' contactPoint="{contact}"' if contact else ""
                out.append(f'      <{tag} elementType="{kind}" elementId="{target}"{cp}/>')
                if kind == "road":
                    lane_link.append(f'<{tag} id="-1"/>')
            out.append("    </link>")
            out.append("    <planView>")
            out.append(f'      <geometry s="0" x="{fmt(rd["x"])}" y="{fmt(rd["y"])}" '
                       f'hdg="{fmt(rd["hdg"])}" length="{fmt(rd["length"])}">')
            if rd["curvature"] == 0.0:
                out.append("        <line/>")
            else:
                out.append(f'        <arc curvature="{fmt(rd["curvature"])}"/>')
            out.append("      </geometry>")
            out.append("    </planView>")
            out.append("    <lanes>")
            out.append(f'      <laneOffset s="0" a="{fmt(self.hw)}" b="0" c="0" d="0"/>')
            out.append('      <laneSection s="0">')
            out.append('        <center><lane id="0" type="none" level="false"/></center>')
            out.append("        <right>")
            out.append('          <lane id="-1" type="driving" level="false">')
            out.append("            <link>" + "".join(lane_link) + "</link>")
            out.append(f'            <width sOffset="0" a="{w}" b="0" c="0" d="0"/>')
            out.append("          </lane>")
            out.append("        </right>")
            out.append("      </laneSection>")
            out.append("    </lanes>")
            out.append("  </road>")
        for j in self.junctions:
            out.append(f'  <junction id="{j["id"]}" name="{j["name"]}">')
            for k, (incoming, connecting, contact) in enumerate(j["connections"]):
                out.append(f'    <connection id="{k}" incomingRoad="{incoming}" connectingRoad="{connecting}" '
                           f'contactPoint="{contact}">')
                out.append('      <laneLink from="-1" to="-1"/>')
                out.append("    </connection>")
            out.append("  </junction>")
        out.append("</OpenDRIVE>")
        return "\n".join(out) + "\n"


N, E, S, W = math.pi / 2, 0.0, -math.pi / 2, math.pi


def site_yaml(name, comment, bounds, road_width, spacing, areas, obstacles, anchors, homes, racks=()):
    lines = [f"# {line}" for line in comment.strip().splitlines()]
    lines += [
        "# Loading areas: yaw points from the pallet towards the road a forklift approaches from;",
        "# the forklift picks facing yaw + pi. Written by maps/tools/make_maps.py.",
        f"name: {name}",
        f"opendrive: {name}.xodr",
        f"bounds: {{min_x: {fmt(bounds[0])}, min_y: {fmt(bounds[1])}, max_x: {fmt(bounds[2])}, max_y: {fmt(bounds[3])}}}",
        f"road_width: {fmt(road_width)}",
        f"graph_spacing: {fmt(spacing)}",
        "loading_areas:",
    ]
    for i, (x, y, yaw, pallet) in enumerate(areas):
        lines.append(f"  - {{id: A{i + 1}, x: {fmt(x)}, y: {fmt(y)}, yaw: {fmt(yaw)}, pallet: {'true' if pallet else 'false'}}}")
    lines.append("static_obstacles:")
    for i, (x0, y0, x1, y1) in enumerate(obstacles):
        lines.append(f"  - {{id: O{i + 1}, enabled: false, polygon: [[{fmt(x0)}, {fmt(y0)}], [{fmt(x1)}, {fmt(y0)}], "
                     f"[{fmt(x1)}, {fmt(y1)}], [{fmt(x0)}, {fmt(y1)}]]}}")
    lines.append("uwb_anchors:")
    for i, (x, y, z) in enumerate(anchors):
        lines.append(f"  - {{id: U{i + 1}, x: {fmt(x)}, y: {fmt(y)}, z: {fmt(z)}}}")
    lines.append("homes:")
    for i, (x, y, yaw) in enumerate(homes):
        lines.append(f"  - {{id: H{i + 1}, x: {fmt(x)}, y: {fmt(y)}, yaw: {fmt(yaw)}}}")
    if racks:
        lines.append("racks:")
        for i, (x0, y0, x1, y1) in enumerate(racks):
            lines.append(f"  - {{id: R{i + 1}, polygon: [[{fmt(x0)}, {fmt(y0)}], [{fmt(x1)}, {fmt(y0)}], "
                         f"[{fmt(x1)}, {fmt(y1)}], [{fmt(x0)}, {fmt(y1)}]]}}")
    return "\n".join(lines) + "\n"


def table_a(site_name="table_a", closed=()):
    # Ring road with a cross: 4 T-junctions on the ring, a crossing in the middle, 4 rounded
    # corners. Road centres at 0.45, 1.5 and 2.55 m leave 0.75 m square courtyards and a 0.30 m
    # band outside the ring for pallets. `closed` names roads left out: a revision of the same
    # table (same loading areas, homes and anchors) that the server can switch robots to.
    net = Network(site_name, 0.30)
    lo, mid, hi = 0.45, 1.5, 2.55
    for name, x, y in [("sw", lo, lo), ("s", mid, lo), ("se", hi, lo), ("w", lo, mid), ("c", mid, mid),
                       ("e", hi, mid), ("nw", lo, hi), ("n", mid, hi), ("ne", hi, hi)]:
        net.node(name, x, y)
    for u, v, name in [("sw", "s", "ring south west"), ("s", "se", "ring south east"), ("se", "e", "ring east south"),
                       ("e", "ne", "ring east north"), ("nw", "n", "ring north west"), ("n", "ne", "ring north east"),
                       ("sw", "w", "ring west south"), ("w", "nw", "ring west north"), ("s", "c", "cross south"),
                       ("c", "n", "cross north"), ("w", "c", "cross west"), ("c", "e", "cross east")]:
        if name not in closed:
            net.edge(u, v, name)
    net.build()
    q1, q2 = 0.975, 2.025  # middles of the ring's half sides
    areas = [(q1, 0.15, N, True), (q2, 0.15, N, False), (2.85, q1, W, True), (2.85, q2, W, False),
             (q2, 2.85, S, True), (q1, 2.85, S, False), (0.15, q2, E, True), (0.15, q1, E, False)]
    # Each closes a road away from every loading area and home, so the ring still serves them all.
    obstacles = [(1.40, 0.85, 1.60, 1.05), (1.40, 1.95, 1.60, 2.15), (0.35, 1.55, 0.55, 1.75), (2.45, 2.25, 2.65, 2.45)]
    anchors = [(0.0, 0.0, 1.0), (3.0, 0.0, 1.0), (3.0, 3.0, 1.0), (0.0, 3.0, 1.0)]
    # Homes inside the courtyards, three to a courtyard: two side by side facing the ring road
    # they leave by, and one nearer the cross facing +x (the thesis starts forklifts at zero
    # heading). A forklift turning on the spot in a lane sweeps 0.15 m from the road centre; every
    # parked body stands at least 9.5 cm beyond that, more than the 8 cm the agents stop at, so
    # parked robots never stop the traffic passing them. The pair stands 0.29 m apart (0.13 m
    # between bodies): one turning on the spot at home keeps 6 cm from its neighbour, beyond the
    # agents' 3 cm safety gap, so a robot leaving home is not stopped by the one parked beside it.
    # Each home of a pair is nearer the ring's south or north side than any other road, so the
    # road it is reached from is not one an obstacle or a revision closes. (Homes 2 cm further
    # from the ring would be nearer the cross or the west ring: robots would be shut in at home
    # while the cross's north arm is closed.)
    def courtyard_homes(x_ring, x_cross, y_ring, y_cross):
        sx = 1.0 if x_cross > x_ring else -1.0
        sy = 1.0 if y_cross > y_ring else -1.0
        facing_ring = S if sy > 0 else N
        return [(x_ring + sx * 0.38, y_ring + sy * 0.37, facing_ring), (x_cross - sx * 0.38, y_ring + sy * 0.37, facing_ring),
                ((x_ring + x_cross) / 2, y_cross - sy * 0.35, 0.0)]
    sw, se = courtyard_homes(lo, mid, lo, mid), courtyard_homes(hi, mid, lo, mid)
    ne, nw = courtyard_homes(hi, mid, hi, mid), courtyard_homes(lo, mid, hi, mid)
    homes = [sw[0], se[0], ne[0], nw[0], sw[1], se[1], ne[1], nw[1], sw[2], se[2], ne[2], nw[2]]
    comment = """Demo table A: 3 m x 3 m, 30 cm single-lane roads driven both ways [Forklift thesis, Fig. 3.1a]:
a ring road with a cross through the middle, 4 T-junctions and a crossing."""
    if closed:
        comment = f"""Demo table A with {', '.join(closed)} closed: the same table, loading areas, homes and
anchors, fewer roads. A revision of table_a: the server can switch its robots to it at runtime."""
    return net, site_yaml(site_name, comment, (0, 0, 3, 3), 0.30, 0.10, areas, obstacles, anchors, homes)


def table_b():
    # A ladder: ring road with two rungs at y = 1.15 and 1.85 joined by a short middle road.
    net = Network("table_b", 0.30)
    lo, hi = 0.45, 2.55
    r1, r2, mid = 1.15, 1.85, 1.5
    for name, x, y in [("sw", lo, lo), ("se", hi, lo), ("w1", lo, r1), ("m1", mid, r1), ("e1", hi, r1),
                       ("w2", lo, r2), ("m2", mid, r2), ("e2", hi, r2), ("nw", lo, hi), ("ne", hi, hi)]:
        net.node(name, x, y)
    for u, v, name in [("sw", "se", "ring south"), ("sw", "w1", "ring west 1"), ("w1", "w2", "ring west 2"),
                       ("w2", "nw", "ring west 3"), ("se", "e1", "ring east 1"), ("e1", "e2", "ring east 2"),
                       ("e2", "ne", "ring east 3"), ("nw", "ne", "ring north"),
                       ("w1", "m1", "rung 1 west"), ("m1", "e1", "rung 1 east"), ("w2", "m2", "rung 2 west"),
                       ("m2", "e2", "rung 2 east"), ("m1", "m2", "middle")]:
        net.edge(u, v, name)
    net.build()
    # Loading areas in the band outside the ring, two on each side, away from the corners.
    areas = [(0.15, 0.80, E, True), (0.15, 2.20, E, False), (2.85, 0.80, W, True), (2.85, 1.50, W, False),
             (1.00, 0.15, N, False), (2.00, 0.15, N, True), (1.00, 2.85, S, True), (2.00, 2.85, S, False)]
    obstacles = [(1.40, 1.40, 1.60, 1.60), (0.35, 1.40, 0.55, 1.60), (2.45, 2.10, 2.65, 2.30), (1.40, 2.45, 1.60, 2.65)]
    anchors = [(0.0, 0.0, 1.0), (3.0, 0.0, 1.0), (3.0, 3.0, 1.0), (0.0, 3.0, 1.0)]
    # Twelve homes clear of the lanes: a row of five between the ring's south side and rung 1, one
    # between rung 2 and the ring's north side, and one in each cell between the rungs. Parked
    # bodies stand 0.27 m from the road centres as on table A; facing +x, the rows' homes are
    # 0.3275 m apart (a robot turning on the spot at home keeps 5 cm from its neighbour, beyond the
    # agents' 3 cm safety gap). Listed round the table, so a smaller fleet starts on every side.
    south = [(1.5 + 0.3275 * k, lo + 0.34, 0.0) for k in (-2, -1, 0, 1, 2)]
    # Each home is 1 cm nearer one road than any other, so the road it is reached from is never a
    # tie between two (the corridor the static grid frees and the agents' nearest graph point then
    # agree). The north row is reached from rung 2, away from the obstacle on the ring's north side.
    north = [(1.5 + 0.3275 * k, r2 + 0.34, 0.0) for k in (-2, -1, 0, 1, 2)]
    cells = [(0.975, r1 + 0.34, 0.0), (2.025, r1 + 0.34, 0.0)]
    homes = [south[0], north[4], south[4], north[0], cells[0], cells[1], south[2], north[2], south[1], north[3],
             south[3], north[1]]
    comment = """Demo table B: 3 m x 3 m, 30 cm single-lane roads driven both ways [Forklift thesis, Fig. 3.1b]:
a ladder of two rungs inside a ring road, six T-junctions."""
    return net, site_yaml("table_b", comment, (0, 0, 3, 3), 0.30, 0.10, areas, obstacles, anchors, homes)


def warehouse():
    # 40 m x 20 m: rack rows along x, 1.2 m deep, with 3 m aisles between their faces [Picker thesis].
    # Aisle roads at y = 4.2, 8.4, 12.6, 16.8 join cross aisles at x = 2, 20 and 38.
    net = Network("warehouse", 1.0)
    ys = [4.2, 8.4, 12.6, 16.8]
    xs = [2.0, 20.0, 38.0]
    for i, y in enumerate(ys):
        for k, x in enumerate(xs):
            net.node(f"n{i}{k}", x, y)
    for i, y in enumerate(ys):
        net.edge(f"n{i}0", f"n{i}1", f"aisle {i + 1} west")
        net.edge(f"n{i}1", f"n{i}2", f"aisle {i + 1} east")
    for k, x in enumerate(xs):
        for i in range(len(ys) - 1):
            net.edge(f"n{i}{k}", f"n{i + 1}{k}", f"cross {k + 1}.{i + 1}")
    net.build()
    # Pallets in the racks: rack faces 1.5 m from an aisle centre, pallet centres 0.9 m from it.
    areas = []
    rack_xs = [4.5 + 1.5 * j for j in range(9)] + [22.5 + 1.5 * j for j in range(9)]
    for i, y in enumerate(ys):
        for side, yaw in ((-1, N), (1, S)):
            for j, x in enumerate(rack_xs):
                areas.append((x, y + side * 0.9, yaw, (i + j) % 2 == 0))
    # Aisle obstacles fit between two pallet columns (1.5 m apart) so they close the aisle only.
    obstacles = [(6.45, 3.7, 7.05, 4.7), (28.95, 12.1, 29.55, 13.1), (19.5, 10.0, 20.5, 11.0), (37.5, 10.0, 38.5, 11.0)]
    # Rack rows 1.2 m deep between the aisles, broken by the middle cross aisle.
    racks = [(x0, y - 0.6, x1, y + 0.6) for y in (2.1, 6.3, 10.5, 14.7, 18.9) for x0, x1 in ((3.5, 18.5), (21.5, 36.5))]
    anchors = [(0.0, 0.0, 4.0), (20.0, 0.0, 4.0), (40.0, 0.0, 4.0), (40.0, 20.0, 4.0), (20.0, 20.0, 4.0),
               (0.0, 20.0, 4.0)]
    # Homes beside the west cross aisle, parked along it, 0.6 m from its centre line.
    homes = [(1.4, 5.0 + 0.9 * k, N) for k in range(12)]
    comment = """Warehouse: 40 m x 20 m, rack rows 1.2 m deep with 3 m aisles [Picker thesis]; 1 m roads on the
aisle centres and three cross aisles; for scale and planner benchmarks."""
    return net, site_yaml("warehouse", comment, (0, 0, 40, 20), 1.0, 0.5, areas, obstacles, anchors, homes, racks)


def big_warehouse(name="big_warehouse", rows_along_x=24, roads_along_y=11, width=200.0, height=100.0):
    # 200 m x 100 m: the warehouse's rack rows, aisles and bays on one regular grid, a road on every
    # grid line. Roads along x every 4.2 m from y = 1.7 (24: the south and north perimeter roads and 22
    # aisles between them) cross roads along y every 18 m from x = 1 (11: the west and east perimeter
    # roads and 9 cross aisles). Each block between two cross aisles has the warehouse's 9 bays.
    # Fewer rows and roads give the same pattern smaller (mid_warehouse).
    net = Network(name, 1.0)
    ys = [1.7 + 4.2 * i for i in range(rows_along_x)]
    xs = [1.0 + 18.0 * k for k in range(roads_along_y)]
    for i, y in enumerate(ys):
        for k, x in enumerate(xs):
            net.node(f"n{i}.{k}", x, y)
    row_name = {0: "south", len(ys) - 1: "north"}
    col_name = {0: "west", len(xs) - 1: "east"}
    for i in range(len(ys)):
        for k in range(len(xs) - 1):
            net.edge(f"n{i}.{k}", f"n{i}.{k + 1}", f"{row_name.get(i, f'aisle {i}')} {k + 1}")
    for k in range(len(xs)):
        for i in range(len(ys) - 1):
            net.edge(f"n{i}.{k}", f"n{i + 1}.{k}", f"{col_name.get(k, f'cross {k}')} {i + 1}")
    net.build()
    # Pallet places in the bays x0 + 2.5 + 1.5 j (j = 0..8) as in the warehouse; two a rack face
    # and block (j = 2 and 6), on both sides of every aisle, 0.9 m from the aisle centre.
    areas = []
    for i, y in enumerate(ys[1:-1], start=1):
        for side, yaw in ((-1, N), (1, S)):
            for n, x in enumerate(x0 + 2.5 + 1.5 * j for x0 in xs[:-1] for j in (2, 6)):
                areas.append((x, y + side * 0.9, yaw, (i + n) % 2 == 0))
    # Rack rows 1.2 m deep between every two roads along x, broken by the cross aisles.
    racks = [(x0 + 1.5, y0 + 2.1 - 0.6, x1 - 1.5, y0 + 2.1 + 0.6) for y0 in ys[:-1] for x0, x1 in zip(xs, xs[1:])]
    # Aisle obstacles, off, between two bays of a block so each closes one aisle only.
    closed = [(i * (rows_along_x - 1) // 24 + 1, min(k * roads_along_y // 11, roads_along_y - 2))
              for i, k in ((3, 1), (8, 8), (15, 3), (20, 9))]
    obstacles = [(xs[k] + 8.2, ys[i] - 0.5, xs[k] + 8.8, ys[i] + 0.5) for i, k in dict.fromkeys(closed)]
    # UWB anchors on the ceiling, a grid at most 20 m apart: every point of the floor has four within
    # the tags' 30 m range.
    nx, ny = math.ceil(width / 20.0), math.ceil(height / 20.0)
    anchors = [(round(width * k / nx, 2), round(height * j / ny, 2), 4.0) for j in range(ny + 1) for k in range(nx + 1)]
    # Homes 0.6 m from a road's centre line, parked along it, 0.9 m apart, at least 1.5 m along the
    # road from any junction: 17 a block outside the south and north perimeter roads, two between
    # two roads along x outside the west and east perimeter roads and west of every cross aisle.
    rows = []
    for y, off in ((ys[0], -0.6), (ys[-1], 0.6)):
        rows += [[(x0 + 1.8 + 0.9 * n, y + off, E) for n in range(17)] for x0 in xs[:-1]]
    for x, off in [(xs[0], -0.6), (xs[-1], 0.6)] + [(x, -0.6) for x in xs[1:-1]]:
        rows += [[(x + off, y0 + 1.65, N), (x + off, y0 + 2.55, N)] for y0 in ys[:-1]]
    # Listed so that any first N spread over the site: each next home is the one farthest from
    # those before it (ties: the earlier in the rows above), from the south-west one on.
    left = [h for row in rows for h in row]
    homes = [left.pop(0)]
    gap = [math.hypot(x - homes[0][0], y - homes[0][1]) for x, y, _ in left]
    while left:
        far = max(range(len(left)), key=lambda n: (gap[n], -n))
        homes.append(left.pop(far))
        gap.pop(far)
        gap = [min(g, math.hypot(x - homes[-1][0], y - homes[-1][1])) for g, (x, y, _) in zip(gap, left)]
    comment = """Big warehouse: 200 m x 100 m, the warehouse's rack rows and 3 m aisles on a regular grid; 1 m
roads on 22 aisle centres, 9 cross aisles and a perimeter road, hundreds of homes; for scale runs of
the server and the load generator (fleetctl traffic-eval)."""
    if name != "big_warehouse":
        comment = f"""{name.replace("_", " ").capitalize()}: {width:.0f} m x {height:.0f} m, the big warehouse's pattern with
{rows_along_x - 2} aisles and {roads_along_y - 2} cross aisles, {len(homes)} homes; for soaks with many agents."""
    return net, site_yaml(name, comment, (0, 0, round(width), round(height)), 1.0, 0.5, areas, obstacles, anchors,
                          homes, racks)


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    for make in (table_a, lambda: table_a("table_a_north_closed", ("cross north",)), table_b, warehouse,
                 big_warehouse, lambda: big_warehouse("mid_warehouse", 8, 4, 56.0, 33.0), plant, lambda: plant("plant_one_lane", 1), lambda: plant("plant_middle_closed", 2, ("middle aisle 2",))):
        net, yaml_text = make()
        with open(os.path.join(out_dir, net.name + ".xodr"), "w") as f:
            f.write(net.xodr())
        with open(os.path.join(out_dir, net.name + ".yaml"), "w") as f:
            f.write(yaml_text)
        print(f"{net.name}: {len(net.roads)} roads, {len(net.junctions)} junctions")


if __name__ == "__main__":
    main()
