"""The plant: a real-scale site, 60 m x 30 m, for several fleets at once (docs/maps.md).

South to north:
- packing stations on two narrow spurs, four more along the south cross aisle by the racks, and a
  high-bay rack facing the south cross aisle;
- the south cross aisle (3.5 m, two lanes, keep right);
- west: the finished-goods corridor, 2.98 m with two lanes of 1.49 m [Stacker thesis, section
  4.1.2], EPAL pallets behind a raised limiter on its north side (they stand 0.30 m up [Stacker
  thesis, section 4.1.3]) and packaging pallets on the floor on its south side;
  east: the rack section, three rack rows with two 3.0 m aisles of two lanes, pillars every
  3.5 m with AR markers [Picker thesis, section 4.2.9.3], a pallet on the floor and one at height
  in every bay;
- the north cross aisle;
- expedition (part of it on a narrow spur), the waiting area and sixteen parking stalls;
- off the south cross aisle, a narrow street with four stalls where the pickers park.

Widths decide who goes where: a vehicle fits a lane when its width plus the plant's 0.10 m
margin is at most the lane's width. The narrow spurs (0.95 m) take a 0.8 m forklift, not a
0.9 m reach truck; every other road (1.1 m and more) takes both. The high rack places are for
the reach trucks by their lift height, and the wide roads reach all of them.
"""

import math

from lane_network import LaneNetwork, ONE, TWO, fmt

N, E, S, W = math.pi / 2, 0.0, -math.pi / 2, math.pi

WIDTH, HEIGHT = 60.0, 30.0
AISLE_LANE = 1.75     # cross aisles: 3.5 m, two lanes
CORRIDOR_LANE = 1.49  # the finished-goods corridor: 2.98 m, two lanes
RACK_LANE = 1.5       # rack aisles: 3.0 m between rack faces, two lanes
NARROW_LANE = 0.95    # single-lane spurs only a 0.8 m vehicle fits
STALL_LANE = 1.1      # the parking street and stalls: a 0.9 m reach truck fits
PICKER_LANE = 0.7     # the pickers' stalls: a 0.50 m Summit-XLS fits, no pallet truck does
BAY_LANE = 0.8        # stacker bays: marked on the floor, narrower than any vehicle plus its margin

SOUTH_Y, NORTH_Y = 7.0, 24.0               # cross aisle centres
WEST_X, MID_X, EAST_X = 2.5, 30.0, 57.5    # north-south aisle centres
CORRIDOR_Y, RACK_AISLE_Y = 17.1, 11.7      # the corridor continues as the upper rack aisle
PACKING_XS, EXPEDITION_SPUR_X, PARKING_X = (8.0, 16.0), 21.0, 36.4
AISLE_PACKING_XS = (27.0, 28.2, 29.4, 30.6)  # packing stations along the south cross aisle, by the racks
STREET_Y, STALL_END_Y = 26.9, 29.1
STALLS = [38.0 + 1.2 * k for k in range(16)]
STACKER_BAYS, STACKER_BAY_END_Y = (6.5, 10.5, 14.5, 25.0), 21.4
PICKERS_X, PICKER_STREET_Y = 20.0, 4.5          # the pickers' access off the south cross aisle, their street
PICKER_STALLS, PICKER_STALL_END_Y = (21.5, 23.0, 24.5, 26.0), 2.5
EAST_MOUTH = 12                            # the reach trucks' street meets its access at stall 13

PALLET_LENGTH, PALLET_WIDTH = 1.2, 0.8     # EPAL; forks enter along the length
CLEARANCE = 0.10                           # pallet to lane edge
LIMITER = (18.6, 18.75)                    # the corridor's raised limiter, y from / to
RACK_X0, BAY, BAYS = 33.5, 3.5, 6          # rack rows: x from, pillar pitch, bays
RACK_ROWS = {"R1": (9.0, 10.2), "R2": (13.2, 15.6), "R3": (18.6, 19.8), "R4": (3.9, 5.1)}
HIGH_LEVELS = (2.2, 4.4)                   # load heights of the upper rack levels, metres


def network(name="plant", corridor_lanes=2, closed=()):
    net = LaneNetwork(name)
    for name, x, y in [("sw", WEST_X, SOUTH_Y), ("sm", MID_X, SOUTH_Y), ("se", EAST_X, SOUTH_Y),
                       ("nw", WEST_X, NORTH_Y), ("nm", MID_X, NORTH_Y), ("ne", EAST_X, NORTH_Y),
                       ("corridor_w", WEST_X, CORRIDOR_Y), ("corridor_e", MID_X, CORRIDOR_Y),
                       ("rack_w", MID_X, RACK_AISLE_Y), ("rack_e", EAST_X, RACK_AISLE_Y),
                       ("upper_e", EAST_X, CORRIDOR_Y),
                       ("expedition", EXPEDITION_SPUR_X, NORTH_Y), ("expedition_end", EXPEDITION_SPUR_X, 29.5),
                       ("parking", PARKING_X, NORTH_Y), ("street_w", PARKING_X, STREET_Y),
                       ("parking_e", STALLS[EAST_MOUTH], NORTH_Y)]:
        net.node(name, x, y)
    for k, x in enumerate(PACKING_XS):
        net.node(f"packing{k + 1}", x, SOUTH_Y)
        net.node(f"packing{k + 1}_end", x, 2.3)
    for k, x in enumerate(STACKER_BAYS):
        net.node(f"stacker{k + 1}", x, NORTH_Y)
        net.node(f"stacker{k + 1}_end", x, STACKER_BAY_END_Y)
    for k, x in enumerate(STALLS):
        net.node(f"street{k + 1}", x, STREET_Y)
        net.node(f"stall{k + 1}", x, STALL_END_Y)
    net.node("pickers", PICKERS_X, SOUTH_Y)
    net.node("picker_street", PICKERS_X, PICKER_STREET_Y)
    for k, x in enumerate(PICKER_STALLS):
        net.node(f"picker_street{k + 1}", x, PICKER_STREET_Y)
        net.node(f"picker_stall{k + 1}", x, PICKER_STALL_END_Y)

    def aisle(nodes, name):
        for k in range(len(nodes) - 1):
            if f"{name} {k + 1}" not in closed:
                net.edge(nodes[k], nodes[k + 1], f"{name} {k + 1}", TWO, AISLE_LANE)

    aisle(["sw", "packing1", "packing2", "pickers", "sm", "se"], "south cross aisle")
    bays = [(x, f"stacker{k + 1}") for k, x in enumerate(STACKER_BAYS)]
    west_of_middle = sorted(bays + [(EXPEDITION_SPUR_X, "expedition")])
    aisle(["nw", *[n for _, n in west_of_middle], "nm", "parking", "parking_e", "ne"], "north cross aisle")
    aisle(["sw", "corridor_w", "nw"], "west aisle")
    aisle(["sm", "rack_w", "corridor_e", "nm"], "middle aisle")
    aisle(["se", "rack_e", "upper_e", "ne"], "east aisle")
    if corridor_lanes == 2:
        net.edge("corridor_w", "corridor_e", "finished-goods corridor", TWO, CORRIDOR_LANE)
    else:
        # The same 2.98 m corridor as one lane driven both ways: robots meeting in it take turns.
        net.edge("corridor_w", "corridor_e", "finished-goods corridor", ONE, 2 * CORRIDOR_LANE)
    net.edge("corridor_e", "upper_e", "rack aisle 2", TWO, RACK_LANE)
    net.edge("rack_w", "rack_e", "rack aisle 1", TWO, RACK_LANE)
    for k in range(len(PACKING_XS)):
        net.edge(f"packing{k + 1}", f"packing{k + 1}_end", f"packing spur {k + 1}", ONE, NARROW_LANE)
    net.edge("expedition", "expedition_end", "expedition spur", ONE, NARROW_LANE)
    # Stacker bays behind the finished-goods row: a stacker reverses in from the aisle as it docks
    # to a pallet and drives out forwards. No vehicle fits a bay as a lane, so no route uses one.
    for k in range(len(STACKER_BAYS)):
        net.edge(f"stacker{k + 1}", f"stacker{k + 1}_end", f"stacker bay {k + 1}", ONE, BAY_LANE)
    # Two dead-end parking streets, one per half of the stall row, each with its own way to the
    # north cross aisle: the forklifts' at the west end, the reach trucks' in the middle of
    # theirs, so that a fleet leaving its stalls at once queues behind its own robots only.
    half = len(STALLS) // 2
    net.edge("parking", "street_w", "parking access west", ONE, STALL_LANE)
    net.edge("parking_e", f"street{EAST_MOUTH + 1}", "parking access east", ONE, STALL_LANE)
    west = ["street_w"] + [f"street{k + 1}" for k in range(half)]
    east = [f"street{k + 1}" for k in range(half, len(STALLS))]
    for name, street in (("west", west), ("east", east)):
        for k in range(len(street) - 1):
            net.edge(street[k], street[k + 1], f"parking street {name} {k + 1}", ONE, STALL_LANE)
    for k in range(len(STALLS)):
        net.edge(f"street{k + 1}", f"stall{k + 1}", f"stall {k + 1}", ONE, STALL_LANE)
    # The pickers' parking: an access off the south cross aisle between the packing stations and
    # the middle aisle, a dead-end street and four stalls 1.5 m apart, all too narrow for any
    # pallet truck (so never one's siding).
    picker_street = ["pickers", "picker_street"] + [f"picker_street{k + 1}" for k in range(len(PICKER_STALLS))]
    for k in range(len(picker_street) - 1):
        net.edge(picker_street[k], picker_street[k + 1], f"picker street {k + 1}", ONE, PICKER_LANE)
    for k in range(len(PICKER_STALLS)):
        net.edge(f"picker_street{k + 1}", f"picker_stall{k + 1}", f"picker stall {k + 1}", ONE, PICKER_LANE)
    net.build()
    return net


def beside(lane_edge, side, clearance=CLEARANCE):
    """Centre of a pallet standing `clearance` beyond a lane edge, its length across the lane."""
    return lane_edge + side * (clearance + PALLET_LENGTH / 2)


def place(kind, x, y, yaw, pallet, actions=None, height=0.0, boxes=None):
    return {"kind": kind, "x": x, "y": y, "yaw": yaw, "pallet": pallet, "actions": actions, "height": height,
            "boxes": boxes}


# Articles on the floor pallets of the rack bays, for the pickers: (length, width, height, kg) of a
# box, none lower than 0.20 m: the arm, 0.80 m up with its elbow kept at 60 degrees or more
# [Picker thesis, Table 10], reaches no lower top face beside the base. The last is too heavy for the picker's gripper (5 kg [Picker thesis, section 3.3]): a pick
# line for it is refused.
# Boxes a packing pallet takes before it goes to expedition: two two-box tours.
BOXES_PER_PALLET = 4
BOX_KINDS = ((0.30, 0.30, 0.25, 3.0), (0.40, 0.30, 0.20, 4.5), (0.30, 0.20, 0.20, 1.5), (0.60, 0.40, 0.30, 12.0))


def box_stock(k):
    """The boxes on the k-th floor pallet of the racks: article A1.. and 6 to 18 boxes."""
    length, width, height, mass = BOX_KINDS[k % len(BOX_KINDS)]
    return {"item": f"A{k + 1}", "count": 6 + (5 * k) % 13, "size": (length, width, height), "mass": mass}


def corridor_and_open_places():
    places = []
    corridor_north_edge = CORRIDOR_Y + CORRIDOR_LANE
    corridor_south_edge = CORRIDOR_Y - CORRIDOR_LANE
    # Finished goods: behind the limiter, standing 0.30 m up on it; stackers only pick them.
    for k in range(16):
        places.append(place("FG", 5.8 + 1.3 * k, LIMITER[1] + PALLET_LENGTH / 2, S, k % 2 == 0, ["pick"], 0.3))
    # Packaging pallets on the floor across the corridor.
    for k in range(10):
        places.append(place("PK", 6.0 + 2.0 * k, beside(corridor_south_edge, -1, 0.05), N, k % 3 == 0))
    assert LIMITER[0] >= corridor_north_edge
    north_edge = NORTH_Y + AISLE_LANE
    for k in range(11):
        places.append(place("EX", 6.0 + 1.2 * k, beside(north_edge, 1), S, k % 2 == 1))
    # Expedition on the narrow spur: forklift-only.
    for k, y in enumerate((26.8, 28.0, 29.2)):
        for side, yaw in ((-1, E), (1, W)):
            x = beside(EXPEDITION_SPUR_X + side * NARROW_LANE / 2, side)
            places.append(place("EN", x, y, yaw, (k + side) % 2 == 0))
    for k in range(6):
        places.append(place("WA", 24.6 + 1.2 * k, beside(north_edge, 1), S, False))
    # Packing stations: pickers drop boxes on the packing pallets, a pallet fleet takes them away.
    for x0 in PACKING_XS:
        for y in (4.1, 2.7):
            for side, yaw in ((-1, E), (1, W)):
                x = beside(x0 + side * NARROW_LANE / 2, side)
                places.append(place("PS", x, y, yaw, True, ["pick", "drop", "dropItem"]))
    # And along the south side of the south cross aisle, between the pickers' street and the
    # high-bay row: a stacker docks to these from the aisle, as at expedition; the spurs are too
    # narrow for it to turn in.
    for x in AISLE_PACKING_XS:
        places.append(place("PS", x, beside(SOUTH_Y - AISLE_LANE, -1), N, True, ["pick", "drop", "dropItem"]))
    return places


def rack_faces():
    """(rack row, face y, direction from the face into the aisle) for every face on an aisle."""
    return [("R1", RACK_ROWS["R1"][1], 1), ("R2", RACK_ROWS["R2"][0], -1), ("R2", RACK_ROWS["R2"][1], 1),
            ("R3", RACK_ROWS["R3"][0], -1), ("R4", RACK_ROWS["R4"][1], 1)]


def rack_places():
    """Every bay has three pallet slots between its pillars; the middle rows show a pallet on the
    floor (boxes for the pickers) and one at height, the high-bay row R4 two at height."""
    places = []
    for row, face_y, into_aisle in rack_faces():
        y = face_y - into_aisle * PALLET_LENGTH / 2
        yaw = N if into_aisle > 0 else S
        for bay in range(BAYS):
            centre = RACK_X0 + BAY * (bay + 0.5)
            if row == "R4":
                places.append(place("RH", centre - 1.05, y, yaw, bay % 2 == 0, None, HIGH_LEVELS[0]))
                places.append(place("RH", centre + 1.05, y, yaw, bay % 2 == 1, None, HIGH_LEVELS[1]))
                continue
            level = HIGH_LEVELS[0] if into_aisle > 0 else HIGH_LEVELS[1]
            floor_pallets = sum(1 for p in places if p["kind"] == "RB")
            places.append(place("RB", centre - 1.05, y, yaw, True, ["pick", "drop", "pickItem"], 0.0,
                                box_stock(floor_pallets)))
            places.append(place("RH", centre + 1.05, y, yaw, bay % 2 == 0, None, level))
    return places


def racks():
    """Rack rows, their front pillars every 3.5 m, and the corridor's limiter."""
    out = [("L1", (5.0, LIMITER[0], 27.0, LIMITER[1]))]
    for row, (y0, y1) in RACK_ROWS.items():
        out.append((row, (RACK_X0, y0, RACK_X0 + BAY * BAYS, y1)))
    for row, face_y, into_aisle in rack_faces():
        for j in range(BAYS + 1):
            x = RACK_X0 + BAY * j
            ys = sorted((face_y, face_y - into_aisle * 0.12))
            out.append((f"{row}-{'N' if into_aisle > 0 else 'S'}{j + 1}", (x - 0.06, ys[0], x + 0.06, ys[1])))
    return out


def markers():
    """AR markers: every 10 m along the open aisles and the corridor, on every front pillar in
    the racks [Picker thesis, section 4.2.9.3]. Where the pickers work outside the racks more
    than the thesis's 10 m, since a marker's range is exact only to about 4 m [Picker thesis,
    section 4.2.9.2.1]: every 5 m along both cross aisles, every 3.5 m on the south wall, as on
    the pillars, at the packing stations and along the middle aisle. Ids are the
    codes printed on them."""
    out = []
    for x in (5.0, 15.0, 25.0, 35.0, 45.0, 55.0):
        out.append((x, NORTH_Y - AISLE_LANE - 0.05, N, 2.0))
        out.append((x, SOUTH_Y + AISLE_LANE + 0.05, S, 2.0))
    # On the corridor limiter's south face every 3.5 m (the first two here, the rest below).
    for x in (5.2, 8.7):
        out.append((x, LIMITER[0], S, 0.3))
    for y in (10.0, 20.0):
        out.append((0.05, y, E, 2.0))
        out.append((WIDTH - 0.05, y, W, 2.0))
    for x in (10.0, 20.0, 30.0):
        out.append((x, SOUTH_Y + AISLE_LANE + 0.05, S, 2.0))
    for k in range(9):
        out.append((3.5 * (k + 1), 0.05, N, 1.0))
    # Where pickers stand to drop boxes, on posts at the aisle end of each packing spur's stations,
    # facing them; along the north cross aisle between the 10 m ones (the middle aisle's mouth
    # is open, so its post stands at the corner); on the ends of the rack rows that face the
    # middle aisle, and across it from rack aisle 1, where pickers turn in.
    for x0 in PACKING_XS:
        for side in (-1, 1):
            out.append((x0 + side * 1.175, 5.0, S, 1.0))
    for x in (10.0, 20.0, MID_X - 2.0, 40.0, 50.0):
        out.append((x, NORTH_Y - AISLE_LANE - 0.05, N, 2.0))
    for row in ("R1", "R2", "R3"):
        out.append((RACK_X0 - 0.05, sum(RACK_ROWS[row]) / 2, W, 1.0))
    out.append((MID_X - AISLE_LANE - 0.05, RACK_AISLE_Y, E, 1.0))
    # The other edge of both cross aisles, between the markers of the first: from the lane beside
    # a row of markers, the two nearest are seen more than 69° off their faces midway, too
    # oblique to decode; across the aisle there is one in view. On the south cross aisle's south
    # edge the packing stations' posts carry one on their aisle face; east of x = 33.5 the
    # high-bay row's pillars do.
    for x in (2.5, 6.825, 9.175, 12.5, 14.825, 17.175, 22.5, 25.0, 32.0):
        out.append((x, SOUTH_Y - AISLE_LANE - 0.05, N, 1.0))
    for x in (7.5, 12.5, 17.5, 32.5, 42.5, 47.5, 57.5):
        out.append((x, NORTH_Y + AISLE_LANE + 0.05, S, 2.0))
    for x in (12.2, 15.7, 19.2, 22.7, 26.2):
        out.append((x, LIMITER[0], S, 0.3))
    # The pickers' stalls: the posts beside their spur carry one on the stalls' face too, as the
    # packing spurs' do. Without them only the south wall's markers are in view from a stall, all
    # on one side, and the position along the wall is poorly held while a picker waits there.
    for x in (22.5, 25.0):
        out.append((x, SOUTH_Y - AISLE_LANE - 0.25, S, 1.0))
    numbered = [(k + 1,) + m for k, m in enumerate(out)]
    for k, (row, face_y, into_aisle) in enumerate(rack_faces()):
        for j in range(BAYS + 1):
            numbered.append((100 + 10 * k + j, RACK_X0 + BAY * j, face_y, N if into_aisle > 0 else S, 1.0))
    return numbered


def site_yaml(places, rack_list, marker_list, name="plant", corridor_lanes=2, closed=()):
    if corridor_lanes != 2:
        header = ("# A design variant of the plant with the finished-goods corridor as one two-way lane, to measure\n"
                  "# what its two lanes are worth (docs/traffic.md); everything else as in plant.yaml.")
    elif closed:
        header = (f"# The plant with {', '.join(closed)} closed: the same places, homes and anchors, fewer roads.\n"
                  "# A revision of plant: the server can switch its robots to it at runtime.")
    else:
        header = "# The plant: 60 m x 30 m at real scale, for several fleets at once; see docs/maps.md."
    lines = [
        header,
        "# Finished-goods corridor 2.98 m with two lanes of 1.49 m [Stacker thesis, section 4.1.2], cross",
        "# aisles 3.5 m and rack aisles 3.0 m with two lanes each (keep right), narrow single-lane spurs",
        "# 0.95 m, rack pillars every 3.5 m with markers [Picker thesis, section 4.2.9.3].",
        "# Places: yaw points from the load towards the road it is handled from. Written by",
        "# maps/tools/make_maps.py.",
        f"name: {name}",
        *(["variant_of: plant"] if corridor_lanes != 2 else []),
        f"opendrive: {name}.xodr",
        f"bounds: {{min_x: 0, min_y: 0, max_x: {fmt(WIDTH)}, max_y: {fmt(HEIGHT)}}}",
        f"road_width: {fmt(CORRIDOR_LANE)}",
        "graph_spacing: 0.5",
        "approach_distance: 1.2",
        "loading_areas:",
    ]
    counts = {}
    for p in places:
        counts[p["kind"]] = counts.get(p["kind"], 0) + 1
        extra = ""
        if p["actions"]:
            extra += f", actions: [{', '.join(p['actions'])}]"
        if p["height"]:
            extra += f", height: {fmt(p['height'])}"
        if p["boxes"]:
            b = p["boxes"]
            extra += (f", boxes: {{item: {b['item']}, count: {b['count']}, "
                      f"size: [{', '.join(fmt(v) for v in b['size'])}], mass: {fmt(b['mass'])}}}")
        lines.append(f"  - {{id: {p['kind']}{counts[p['kind']]}, x: {fmt(p['x'])}, y: {fmt(p['y'])}, "
                     f"yaw: {fmt(p['yaw'])}, pallet: {'true' if p['pallet'] else 'false'}{extra}}}")
    # Designated obstacles, off at start: each closes a cross aisle between two junctions.
    lines.append("static_obstacles:")
    for name, (x0, y0, x1, y1) in (("O1", (11.5, 5.6, 12.5, 8.4)), ("O2", (44.5, 22.6, 45.5, 25.4))):
        lines.append(f"  - {{id: {name}, enabled: false, polygon: [[{fmt(x0)}, {fmt(y0)}], [{fmt(x1)}, {fmt(y0)}], "
                     f"[{fmt(x1)}, {fmt(y1)}], [{fmt(x0)}, {fmt(y1)}]]}}")
    lines.append("uwb_anchors:")
    # UWB anchors under the roof on a 20 m x 15 m grid: round the walls and two over the middle.
    anchors = [(0, 0), (20, 0), (40, 0), (60, 0), (60, 15), (60, 30), (40, 30), (20, 30), (0, 30), (0, 15),
               (20, 15), (40, 15)]
    for k, (x, y) in enumerate(anchors):
        lines.append(f"  - {{id: U{k + 1}, x: {fmt(x)}, y: {fmt(y)}, z: 4}}")
    # Stalls: the forklifts' in the west half of the row, the reach trucks' in the east half,
    # parked facing the street at the stall's end. Each fleet's stalls are numbered from its
    # street's mouth, so the first robots of a fleet park nearest the way out.
    lines.append("homes:")
    east = sorted(range(8, 16), key=lambda k: (abs(k - EAST_MOUTH), k))
    for k, x in enumerate(STALLS):
        home = f"PF{k + 1}" if k < 8 else f"PR{east.index(k) + 1}"
        lines.append(f"  - {{id: {home}, x: {fmt(x)}, y: {fmt(STALL_END_Y)}, yaw: {fmt(S)}}}")
    # Stackers park in their bays facing the aisle, the fork tips 0.6 m clear of the pallets.
    for k, x in enumerate(STACKER_BAYS):
        lines.append(f"  - {{id: PT{k + 1}, x: {fmt(x)}, y: {fmt(STACKER_BAY_END_Y)}, yaw: {fmt(N)}}}")
    # Pickers park at their stalls' ends facing their street.
    for k, x in enumerate(PICKER_STALLS):
        lines.append(f"  - {{id: PP{k + 1}, x: {fmt(x)}, y: {fmt(PICKER_STALL_END_Y)}, yaw: {fmt(N)}}}")
    lines.append("racks:")
    for name, (x0, y0, x1, y1) in rack_list:
        lines.append(f"  - {{id: {name}, polygon: [[{fmt(x0)}, {fmt(y0)}], [{fmt(x1)}, {fmt(y0)}], "
                     f"[{fmt(x1)}, {fmt(y1)}], [{fmt(x0)}, {fmt(y1)}]]}}")
    lines.append("markers:")
    for marker_id, x, y, yaw, z in marker_list:
        lines.append(f"  - {{id: {marker_id}, x: {fmt(x)}, y: {fmt(y)}, z: {fmt(z)}, yaw: {fmt(yaw)}}}")
    # The packing chain: pickers fill the packing pallets; a full one goes to expedition and an
    # empty pallet from the packaging corridor takes its place.
    lines.append("packing:")
    lines.append(f"  boxes_per_pallet: {BOXES_PER_PALLET}")
    for key, kind in (("stations", "PS"), ("full_pallets_to", "EX"), ("empty_pallets_from", "PK")):
        lines.append(f"  {key}: [{', '.join(f'{kind}{k + 1}' for k in range(counts[kind]))}]")
    return "\n".join(lines) + "\n"


def plant(name="plant", corridor_lanes=2, closed=()):
    net = network(name, corridor_lanes, closed)
    places = corridor_and_open_places() + rack_places()
    return net, site_yaml(places, racks(), markers(), name, corridor_lanes, closed)
