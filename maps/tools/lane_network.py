"""Road networks with two-lane roads, single-lane roads and lane widths that differ, as OpenDRIVE.

A network is drawn as straight segments between nodes. A segment is either a two-lane road (a
right lane -1 and a left lane +1 of one width, the reference line between them, so traffic keeps
right under OpenDRIVE's right-hand traffic) or a single-lane road (lane -1 centred on the
reference line, which Fleet drives both ways). Every node where two or more segments meet is a
junction holding one connecting road for every pair of arms: a straight piece or a quarter arc of
radius t, where t is the widest arm's half width, so the connecting roads stay inside the square
the crossing covers.

A connecting road has two lanes when either arm has two, one lane otherwise. Its lane width runs
linearly from the first arm's to the second's, so every lane a vehicle drives on is at least as
wide as the narrower of the two roads it joins: the width that decides which vehicles fit.
Where a single-lane road meets a two-lane one, both lanes of the connecting road end on the
single lane's centre line (a road mouth twice the single lane's width).

Two-lane roads never end in a dead end: their right lane would be a one-way street into nowhere.
"""

import math


def fmt(v):
    return f"{v:.6f}".rstrip("0").rstrip(".") if v != 0 else "0"


TWO, ONE = "two", "one"


def corner(network, node, da, db, r):
    """The connecting road of a junction from the arm leaving along `da` to the one leaving along
    `db`, `r` from the node: its start heading, length and curvature (a quarter circle or a
    straight). Other angles stop the generator naming the node."""
    h1 = math.atan2(-da[1], -da[0])
    h2 = math.atan2(db[1], db[0])
    turn = math.atan2(math.sin(h2 - h1), math.cos(h2 - h1))
    if abs(abs(turn) - math.pi / 2) < 1e-9:
        return h1, r * math.pi / 2, turn / (r * math.pi / 2)
    if abs(turn) < 1e-9:
        return h1, 2 * r, 0.0
    raise SystemExit(f"{network}: node {node} meets at an angle the generator does not draw")


class LaneNetwork:
    def __init__(self, name):
        self.name = name
        self.nodes = {}
        self.edges = []  # dicts: u, v, name, kind, width (one lane's width)
        self.roads = []
        self.junctions = []

    def node(self, name, x, y):
        if name in self.nodes:
            raise SystemExit(f"{self.name}: node {name} is defined twice")
        self.nodes[name] = (x, y)

    def edge(self, u, v, name, kind, width):
        self.edges.append({"u": u, "v": v, "name": name, "kind": kind, "width": width})

    @staticmethod
    def half_width(edge):
        return edge["width"] if edge["kind"] == TWO else edge["width"] / 2.0

    def _arms(self):
        arms = {n: [] for n in self.nodes}
        for i, e in enumerate(self.edges):
            (ux, uy), (vx, vy) = self.nodes[e["u"]], self.nodes[e["v"]]
            length = math.hypot(vx - ux, vy - uy)
            d = ((vx - ux) / length, (vy - uy) / length)
            arms[e["u"]].append((i, d, "start"))
            arms[e["v"]].append((i, (-d[0], -d[1]), "end"))
        return arms

    def build(self):
        arms = self._arms()
        trim = {n: (max(self.half_width(self.edges[i]) for i, _, _ in a) if len(a) >= 2 else 0.0)
                for n, a in arms.items()}
        for n, a in arms.items():
            if len(a) == 1 and self.edges[a[0][0]]["kind"] == TWO:
                raise SystemExit(f"{self.name}: two-lane road {self.edges[a[0][0]]['name']} ends at {n} in a dead end")
        edge_road = {}
        for i, e in enumerate(self.edges):
            (ux, uy), (vx, vy) = self.nodes[e["u"]], self.nodes[e["v"]]
            length = math.hypot(vx - ux, vy - uy)
            d = ((vx - ux) / length, (vy - uy) / length)
            t0, t1 = trim[e["u"]], trim[e["v"]]
            if length - t0 - t1 <= 1e-6:
                raise SystemExit(f"{self.name}: edge {e['u']}-{e['v']} is too short for its junctions")
            road = {"id": str(i + 1), "name": e["name"], "junction": "-1", "x": ux + t0 * d[0], "y": uy + t0 * d[1],
                    "hdg": math.atan2(d[1], d[0]), "length": length - t0 - t1, "curvature": 0.0,
                    "kind": e["kind"], "w0": e["width"], "w1": e["width"], "pred": None, "succ": None, "lanes": {}}
            edge_road[i] = road
            self.roads.append(road)
        next_id = 1000
        for n, node_arms in arms.items():
            if len(node_arms) < 2:
                continue
            junction = {"id": str(len(self.junctions) + 1), "name": n, "connections": []}
            self.junctions.append(junction)
            for i, _, end in node_arms:
                edge_road[i]["pred" if end == "start" else "succ"] = ("junction", junction["id"], None)
            for ai, a in enumerate(node_arms):
                for b in node_arms[ai + 1:]:
                    self._connect(n, trim[n], a, b, edge_road, junction, str(next_id))
                    next_id += 1

    def _connect(self, node, t, a, b, edge_road, junction, road_id):
        (ia, da, ea), (ib, db, eb) = a, b
        ra, rb = edge_road[ia], edge_road[ib]
        px, py = self.nodes[node]
        h1, length, curvature = corner(self.name, node, da, db, t)
        kind = TWO if TWO in (ra["kind"], rb["kind"]) else ONE
        road = {"id": road_id, "name": f"{node} {ra['name']} / {rb['name']}", "junction": junction["id"],
                "x": px + t * da[0], "y": py + t * da[1], "hdg": h1, "length": length, "curvature": curvature,
                "kind": kind, "w0": ra["w0"], "w1": rb["w0"],
                "pred": ("road", ra["id"], ea), "succ": ("road", rb["id"], eb), "lanes": {}}
        lane_ids = (-1, 1) if kind == TWO else (-1,)
        # The arm's lane each lane of this road continues from (at its start) or into (at its end).
        # Two-lane roads meeting end to start run the same way and keep their ids; head to head,
        # right and left swap.
        for lane in lane_ids:
            road["lanes"][lane] = (self._arm_lane(ra, lane, ea == "end"), self._arm_lane(rb, lane, eb == "start"))
        self.roads.append(road)
        for arm, contact, idx in ((ra, "start", 0), (rb, "end", 1)):
            links = sorted({(road["lanes"][lane][idx], lane) for lane in lane_ids})
            if arm["kind"] == ONE:
                links = [(-1, -1)]  # the single lane enters the first; the road's lane links join the rest
            junction["connections"].append((arm["id"], road["id"], contact, links))

    @staticmethod
    def _arm_lane(arm, lane, same_orientation):
        if arm["kind"] == ONE:
            return -1
        return lane if same_orientation else -lane

    def _lanes_xml(self, rd):
        out = []
        length = rd["length"]
        slope = (rd["w1"] - rd["w0"]) / length
        if rd["kind"] == ONE:
            out.append(f'      <laneOffset s="0" a="{fmt(rd["w0"] / 2)}" b="{fmt(slope / 2)}" c="0" d="0"/>')
        out.append('      <laneSection s="0">')

        def lane_xml(lane):
            links = rd["lanes"].get(lane)
            link = ""
            if links:
                pred, succ = links
                link = f'<predecessor id="{pred}"/><successor id="{succ}"/>'
            return ([f'          <lane id="{lane}" type="driving" level="false">',
                     f"            <link>{link}</link>",
                     f'            <width sOffset="0" a="{fmt(rd["w0"])}" b="{fmt(slope)}" c="0" d="0"/>',
                     "          </lane>"])

        if rd["kind"] == TWO:
            out += ["        <left>"] + lane_xml(1) + ["        </left>"]
        out.append('        <center><lane id="0" type="none" level="false"/></center>')
        out += ["        <right>"] + lane_xml(-1) + ["        </right>"]
        out.append("      </laneSection>")
        return out

    def xodr(self):
        out = ['<?xml version="1.0" encoding="UTF-8"?>', "<OpenDRIVE>",
               f'  <header revMajor="1" revMinor="6" name="{self.name}" version="1" '
               'date="2026-11-21" north="0" south="0" east="0" west="0"/>']
        for rd in self.roads:
            out.append(f'  <road name="{rd["name"]}" length="{fmt(rd["length"])}" id="{rd["id"]}" '
                       f'junction="{rd["junction"]}" rule="RHT">')
            out.append("    <link>")
            for key, tag in (("pred", "predecessor"), ("succ", "successor")):
                if rd[key]:
                    kind, target, contact = rd[key]
                    cp = f' contactPoint="{contact}"' if contact else ""
                    out.append(f'      <{tag} elementType="{kind}" elementId="{target}"{cp}/>')
            out.append("    </link>")
            out.append("    <planView>")
            out.append(f'      <geometry s="0" x="{fmt(rd["x"])}" y="{fmt(rd["y"])}" '
                       f'hdg="{fmt(rd["hdg"])}" length="{fmt(rd["length"])}">')
            out.append("        <line/>" if rd["curvature"] == 0.0 else f'        <arc curvature="{fmt(rd["curvature"])}"/>')
            out.append("      </geometry>")
            out.append("    </planView>")
            out.append("    <lanes>")
            out += self._lanes_xml(rd)
            out.append("    </lanes>")
            out.append("  </road>")
        for j in self.junctions:
            out.append(f'  <junction id="{j["id"]}" name="{j["name"]}">')
            for k, (incoming, connecting, contact, links) in enumerate(j["connections"]):
                out.append(f'    <connection id="{k}" incomingRoad="{incoming}" connectingRoad="{connecting}" '
                           f'contactPoint="{contact}">')
                for src, dst in links:
                    out.append(f'      <laneLink from="{src}" to="{dst}"/>')
                out.append("    </connection>")
            out.append("  </junction>")
        out.append("</OpenDRIVE>")
        return "\n".join(out) + "\n"
