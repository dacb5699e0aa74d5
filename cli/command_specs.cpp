#include "cli/command_specs.hpp"

#include "cli/fleet_run.hpp"
#include "orders/order_request_check.hpp"

namespace fleet::cli::specs {

namespace {

const std::vector<std::string> kOrderStates{"QUEUED", "ASSIGNED", "ACTIVE", "DONE", "FAILED", "CANCELLED"};

}  // namespace

std::vector<CommandSpec> server_commands() {
  return {
      {Group::kServer,
       "order",
       "add",
       "",
       false,
       {choice("--kind", {"transport", "move", "pick"}, "K"), value("--from", "AREA"), value("--to", "PLACE", true),
        value("--lines", "FILE.csv"), choice("--handling", {"tray", "loader", "auto"}, "H"),
        integer("--priority", "P", orders::kMinPriority, orders::kMaxPriority), value("--robot", "R"),
        value("--fleet", "F"), on_off("--wait")},
       "create an order, print its id: a transport --from AREA --to AREA (the default\n"
       "kind), a move --to PARKING (go there and stay), a pick --lines FILE.csv --to\n"
       "PLACE (place,item,quantity per line; one order per tour, their ids printed);\n"
       "--handling loader works the list as one walk, each box set on the pallet of a\n"
       "stacker behind the picker (no --to; auto: loader when a stacker and an empty\n"
       "pallet are free, else tray);\n"
       "only fleets that can do its actions take it (exit 2 when none can, or for a\n"
       "line no place can give); --wait follows it to its end (exit 0 DONE, 1 FAILED\n"
       "or CANCELLED)"},
      {Group::kServer,
       "order",
       "list",
       "",
       false,
       {choice("--state", kOrderStates, "S")},
       "the orders the server knows"},
      {Group::kServer, "order", "show", "ID", false, {}, "one order with its history"},
      {Group::kServer, "order", "cancel", "ID", false, {}, "cancel an order (exit 1 when it already ended)"},
      {Group::kServer,
       "order",
       "watch",
       "[ID]",
       false,
       {},
       "live progress: state, phase, robot, elapsed and estimated time left (sim s);\n"
       "redrawn in place on a terminal, one line per change when piped (--json: JSON\n"
       "lines); with ID it ends with the order (exit 0 DONE, 1 FAILED or CANCELLED),\n"
       "without ID at --timeout or Ctrl-C"},
      {Group::kServer,
       "inject",
       "",
       "",
       false,
       {integer("--count", "M", 1, 100000), value("--rate", "N/min"), process_seed(),
        integer("--priority", "P", orders::kMinPriority, orders::kMaxPriority), file("--file", "ORDERS.csv"),
        on_off("--wait")},
       "random valid orders (--count M, --rate N/min, default 60/min; --seed S) or the\n"
       "rows of a CSV file (from,to,priority,delay_s; checked whole before any is sent);\n"
       "prints one line per order; --wait follows them all and prints a summary"},
      {Group::kServer, "obstacle", "list", "", false, {}, "the designated static obstacles, on or off"},
      {Group::kServer, "obstacle", "on", "ID", false, {}, "switch an obstacle on (robots avoid it)"},
      {Group::kServer, "obstacle", "off", "ID", false, {}, "switch an obstacle off"},
      {Group::kServer, "pause", "", "ROBOT", false, {}, "stop a robot where it is (PAUSED)"},
      {Group::kServer, "resume", "", "ROBOT", false, {}, "let a paused robot go on"},
      {Group::kServer, "auto-orders", "on", "", false, {}, "the server creates random orders for free robots"},
      {Group::kServer, "auto-orders", "off", "", false, {}, "no more automatic orders (open ones go on)"},
      {Group::kServer, "map", "list", "", false, {}, "the maps the server knows, and the one it serves"},
      {Group::kServer,
       "map",
       "set",
       "MAP",
       false,
       {value("--robot", "R")},
       "switch every robot (or one, when traffic is off) to another map of the site;\n"
       "agents replan on it"},
      {Group::kServer,
       "robots",
       "",
       "",
       false,
       {on_off("--all")},
       "table of the robots that reported: fleet, state, pose, order, localization score, health;\n"
       "--all adds the configured robots not seen"},
      {Group::kServer,
       "traffic",
       "show",
       "[ROBOT]",
       false,
       {},
       "every robot's traffic grant (status, how far, how long it waited) and whom it\n"
       "waits for; with ROBOT its chain of waits and the route points granted"},
      {Group::kServer,
       "servers",
       "",
       "",
       false,
       {},
       "the fleet's server processes: which is active, in which term and since when, and how\n"
       "long ago each standby last heard it (a standby: fleet-server --standby)"},
      {Group::kServer,
       "stats",
       "",
       "",
       false,
       {},
       "orders by state, done per hour, mean and p95 order time, robot utilisation"},
      {Group::kServer,
       "routing-age",
       "",
       "",
       false,
       {number("--seconds", "S=10", 1.0, 3600.0)},
       "a pose's age on arrival, straight from the robot vs routed by the server"},
  };
}

/// Commands that start a server and agents of their own.
std::vector<CommandSpec> fleet_starting_commands() {
  return {
      {Group::kStartsFleet,
       "demo",
       "",
       "",
       false,
       {integer("--agents", "N=4", 1, kMaxAgents), value("--site", "NAME"), number("--duration", "SECONDS", 0.0, 1e7),
        number("--time-scale", "K", 0.01, 100.0), process_seed(), integer("--http-port", "P=8080", 0, 65535),
        on_off("--no-auto-orders"), integer("--vda5050-vehicles", "N=0", 0, kMaxAgents), on_off("--standby")},
       "one fleet-server and N fleet-agents with automatic orders (off with\n"
       "--no-auto-orders); Ctrl-C or --duration (wall seconds) stops them all\n"
       "and prints a summary; the web view's address (with its token) is printed at start;\n"
       "--vda5050-vehicles N adds N simulated VDA 5050 vehicles driven by fleet-vda5050\n"
       "over a broker of the run's own (docs/vda5050.md); --standby adds a second server\n"
       "as standby, which takes over when the first is killed (its web view on the next port)"},
      {Group::kStartsFleet,
       "soak",
       "",
       "",
       false,
       {integer("--agents", "N=4", 1, kMaxAgents), value("--site", "NAME"),
        number("--duration", "SECONDS=180", 1.0, 1e7), number("--time-scale", "K=10", 0.01, 100.0), process_seed(),
        choice("--traffic", {"on", "off"}), value("--faults", "LIST"), value("--set", "KEY=VALUE"),
        value("--agent-wrap", "WORDS"), integer("--http-port", "P=0", 0, 65535), on_off("--verbose"),
        integer("--vda5050-vehicles", "N=0", 0, kMaxAgents), on_off("--standby"), value("--standby-wrap", "WORDS"),
        on_off("--keep-tracks")},
       "the demo's fleet under ground-truth watch: collisions, deadlocks (an order\n"
       "without progress for 60 s sim), lost and duplicated orders; --faults all|none|\n"
       "kill-agent,stall-agent,kill-server,obstacles,map-switch,kill-host on a schedule\n"
       "from --seed; exit 0 only when nothing was lost, duplicated, collided or\n"
       "deadlocked; --standby: a second server as standby (--standby-wrap WORDS before its\n"
       "command), kill-host kills the active one, which comes back 5 s later as standby;\n"
       "--verbose: debug logs of every process in the run directory; --keep-tracks: every\n"
       "robot's track of the whole run in its tracks.csv (fleetctl map render --tracks)"},
      {Group::kStartsFleet,
       "load",
       "",
       "",
       false,
       {integer("--robots", "N=50", 1, 5000), value("--site", "NAME"), number("--duration", "SECONDS=120", 1.0, 1e6),
        number("--warmup", "SECONDS=10", 0.0, 600.0), number("--time-scale", "K=1", 0.1, 10.0), process_seed(),
        value("--fleet", "ID"), value("--set", "KEY=VALUE"), on_off("--verbose")},
       "a load test of the server: a real fleet-server (automatic orders, traffic,\n"
       "its database and one web stream client) against N emulated robots on one DDS\n"
       "participant (a load generator: kinematic, exact poses, no sensors) that speak\n"
       "to it as agents do; prints server CPU and memory, traffic cycle and dispatch\n"
       "times, grant latency, wire rates and orders done; exit 0 when every robot\n"
       "reported and none collided or deadlocked; --set KEY=VALUE (repeatable) sets a\n"
       "setting for the server and the emulated robots alike"},
  };
}

/// Commands that read and draw sites, with no DDS.
std::vector<CommandSpec> map_commands() {
  return {
      {Group::kOffline,
       "map",
       "check",
       "SITE.yaml|GRID.map ...",
       true,
       {on_off("--strict")},
       "validate sites: roads, graph, loading areas and their reachability;\n"
       "a grid site (GRID.map): free cells, components, dead ends;\n"
       "--strict: the road network's warnings are errors"},
      {Group::kOffline,
       "map",
       "sample",
       "FILE.xodr",
       true,
       {number("--step", "M", 1e-6, 1e9), integer("--max-rows", "N", 1, 1e12), number("--tolerance", "M", 0.0, 1e3),
        on_off("--strict")},
       "CSV road_id,s,x,y,hdg along every reference line, row by row, at most\n"
       "--max-rows (10,000,000); --strict: warnings are errors"},
      {Group::kOffline,
       "map",
       "render",
       "SITE.yaml",
       true,
       {file("-o", "FILE.svg", true), on_off("--no-points"), file("--tracks", "TRACKS.csv"),
        number("--since", "S", -1e12, 1e12)},
       "an SVG picture of a site; --tracks draws the robots' tracks a soak wrote\n"
       "beside a deadlock or collision report (from --since S sim seconds on)"},
  };
}

/// Commands that evaluate a part on core/ alone, beside the theses' figures or a benchmark.
std::vector<CommandSpec> evaluation_commands() {
  return {
      {Group::kOffline,
       "loc-eval",
       "",
       "",
       false,
       {choice("--trajectory", {"square", "figure8", "table_a_loop", "rack_aisle", "plant_route"}),
        number("--duration", "S", 1e-3, 36000.0), seed(), number("--nlos", "F", 0.0, 1.0), file("--plot", "FILE.svg")},
       "localization on core/ alone: raw UWB vs EKF errors; rack_aisle: the picker on the\n"
       "plant's rack aisle, localised by markers and wheel odometry; plant_route: the same\n"
       "picker on its round from parking to a rack, a packing station and back at 1 m/s\n"
       "(--nlos and --plot do not apply to either)"},
      {Group::kOffline,
       "plan-eval",
       "",
       "",
       false,
       {value("--site", "NAME", true), integer("--queries", "N", 1, 1000000), seed(),
        number("--resolution", "M", 0.005, 1.0), number("--optimal-budget-ms", "MS", 1e-3, 60000.0),
        on_off("--no-ompl")},
       "road_astar, grid_astar, grassfire, ompl_rrtconnect and ompl_bitstar on the same\n"
       "random start/goal pairs of maps/NAME.yaml: per planner the median and p95 time, the\n"
       "success rate and the mean path length relative to the shortest any planner found"},
      {Group::kOffline,
       "ctrl-eval",
       "",
       "",
       false,
       {seed(), integer("--runs", "N", 0, 100000), value("--site", "NAME"), number("--speed", "V", 0.01, 1.0),
        choice("--follower", {"seed", "regulated"}), on_off("--gyro-cal"), file("--plot", "F.svg")},
       "path tracking on the site's standard paths (perfect localization and EKF, the\n"
       "thesis's follower and the regulated one), then N pick-and-drop orders with sensor\n"
       "noise, on core/ alone; --gyro-cal subtracts a gyro bias estimated at standstill\n"
       "before the EKF (the agent does not; it shows what it would bring)"},
      {Group::kOffline,
       "dock-eval",
       "",
       "",
       false,
       {integer("--runs", "N", 1, 10000), seed(), value("--pose-noise", "CM,DEG"), on_off("--no-sweeps"),
        file("--plot", "F.svg")},
       "the stacker's docking runs and detection ranges on core/ alone, beside the thesis's (exit 1 below\n"
       "99 % docked)"},
      {Group::kOffline,
       "pick-eval",
       "",
       "",
       false,
       {seed(), value("--drop", "PLACE")},
       "the picker on core/ alone beside the thesis's figures: aisle tests I-III,\n"
       "marker error against distance, arm pick cycle, job cycle and items per hour\n"
       "on maps/plant_pick_list.csv, dropped at --drop PLACE (default the first packing\n"
       "station) (exit 1 when a target is missed)"},
      {Group::kOffline,
       "traffic-eval",
       "",
       "",
       false,
       {value("--site", "NAME"), value("--against", "SITE"), integer("--robots", "N", 1, 200),
        number("--duration", "S", 1.0, 1e6), number("--dwell", "S", 0.0, 600.0), seed(), value("--places", "P1,P2"),
        choice("--core", {"manager", "pibt", "both"}), choice("--lanes", {"both", "one-way"}),
        value("--delay", "P,MIN,MAX"), on_off("--verbose")},
       "the traffic manager with the fleets' vehicle types on a site, robots driven\n"
       "kinematically (a load generator) on random trips (--places FG,EX: only between\n"
       "places whose ids start so); --against SITE runs the same on a revision and\n"
       "prints the ratio of trips; --core pibt coordinates the same trips with the\n"
       "coordination core's place planner, --core both runs both and prints the ratio;\n"
       "--lanes one-way has the planner drive the manager's one-way corridors (default\n"
       "both ways); --delay P,MIN,MAX (--core pibt) stops each move with probability P\n"
       "for MIN..MAX seconds; --verbose lists each stall with its chain of waits"},
      {Group::kOffline,
       "mapf-eval",
       "",
       "",
       false,
       {file("--instance", "FILE.json", true), integer("--steps", "N", 1, 1000000), integer("--window", "W", 1, 50),
        choice("--planner", {"operations", "cells"}), choice("--guidance", {"on", "off"}),
        integer("--lns-window", "H", 0, 64), integer("--lns-rounds", "N", 0, 100000), integer("--lns-size", "K", 1, 64),
        value("--delay", "P,MIN,MAX"), seed(), file("--output", "OUT.json")},
       "the coordination core on a League of Robot Runners 2023 instance in the\n"
       "competition's discrete model (default 1000 steps); --planner cells plans a\n"
       "next cell per robot instead of a sequence of actions (window 2, else 3);\n"
       "--guidance off steers robots by the shortest way, not by guide paths;\n"
       "--lns-window H plans H steps (default 6; 0: the operations alone) and\n"
       "improves them by N (--lns-rounds, default 30 a robot) neighbourhood\n"
       "searches of K robots (--lns-size, default 8);\n"
       "--delay holds each robot\n"
       "with probability P for MIN..MAX steps; --output writes the competition's\n"
       "output file; prints errands a step, planning time a step and the longest\n"
       "standstill (exit 1 when a step broke the rules or a wait cycle formed)"},
  };
}

/// Commands that read or write files alone: the fleets of a configuration, security folders,
/// the configuration keys, shell completion.
std::vector<CommandSpec> tool_commands() {
  return {
      {Group::kOffline,
       "fleets",
       "",
       "",
       false,
       {value("--site", "NAME")},
       "every fleet of the configuration with its vehicle profile; --json: VDA 5050 factsheets"},
      {Group::kOffline,
       "security",
       "init",
       "DIR",
       true,
       {value("--site", "NAME"), integer("--days", "N", 1, 36500), on_off("--force"), value("--web-hosts", "NAME,...")},
       "credentials for DDS Security in DIR: an identity and a permissions\n"
       "authority, the signed governance, and for the server, the operator and\n"
       "every robot of the site's fleets a key, a certificate and signed\n"
       "permissions, valid N days (default 365); --force replaces authorities\n"
       "already in DIR; an HTTPS certificate for the web view, for --web-hosts\n"
       "(default localhost,127.0.0.1) (docs/security.md)"},
      {Group::kOffline,
       "security",
       "check",
       "DIR",
       true,
       {},
       "every certificate of a security folder and when it expires, soonest first\n"
       "(exit 1 when one has expired)"},
      {Group::kOffline,
       "config",
       "keys",
       "",
       false,
       {on_off("--markdown")},
       "every configuration key with default, unit, range and meaning; --markdown: docs/configuration.md"},
      {Group::kOffline,
       "completion",
       "bash",
       "",
       false,
       {},
       "a bash completion script: source <(fleetctl completion bash)"},
  };
}

}  // namespace fleet::cli::specs
