#!/usr/bin/env bash
# Replays what `fleetctl mapf-eval` writes in the League of Robot Runners 2023 Start-Kit's own
# simulator (its evaluation mode), so that Fleet's output is judged by the competition's action
# model and not by Fleet's. The Start-Kit is copied from the shared data folder into a scratch
# folder under the build tree, mended there (see the patch below) and built in Release.
#   startkit_replay_test.sh SOURCE_DIR BUILD_DIR
# The data folder is $FLEET_LORR_DATA, by default SOURCE_DIR/../shared/data/lorr.
# Cases: random-32-32-20 with 100 robots, the same with delays, warehouse_small with 60 robots,
# random-32-32-20 with the window search and delays, each 200 steps: the replay must be valid, without errors, finish the same number of tasks and
# move every robot as the file says. Then a file with one robot driven straight on for the whole
# run must be rejected, which shows the replay can fail at all.
# Exit 0 when all holds, 1 with the reason otherwise, 77 (skipped) when the data folder is absent.
# The scratch folder is removed on success and kept, with its logs, on failure.
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
lorr=${FLEET_LORR_DATA:-$src/../shared/data/lorr}
kit="$lorr/startkit-2023"
steps=200
fail() { echo "startkit_replay_test: $*" >&2; exit 1; }

if [ ! -f "$kit/src/driver.cpp" ]; then
  echo "startkit_replay_test: skipped: no Start-Kit at $kit (set FLEET_LORR_DATA to the folder that holds startkit-2023/)" >&2
  exit 77
fi
random_instance="$lorr/random.domain/EI23-random_100.json"
warehouse_instance="$lorr/warehouse.domain/EI23-warehouse_small_60.json"
for f in "$random_instance" "$warehouse_instance"; do
  [ -f "$f" ] || fail "the data folder $lorr lacks $f"
done
fleetctl="$build/bin/fleetctl"
[ -x "$fleetctl" ] || fail "$fleetctl is not built"
for tool in python3 patch cmake; do
  command -v "$tool" >/dev/null || fail "$tool is not installed (scripts/install-deps)"
done

mkdir -p "$build/tests/mapf"
work=$(mktemp -d "$build/tests/mapf/startkit-replay.XXXXXX")
trap 'status=$?; if [ $status -eq 0 ]; then rm -rf "$work"; else echo "startkit_replay_test: files kept in $work" >&2; fi' EXIT

# --- The Start-Kit, mended in its copy ---------------------------------------------------------
cp -r "$kit" "$work/startkit"
rm -rf "$work/startkit/build"
# Mends, each needed for a replay to mean anything:
#  (1) DummyPlanner, the planner of evaluation mode, declares `plan(int)`, which overrides
#      nothing: the simulator calls `plan(int, std::vector<Action>&)`, so the base class's naive
#      planner drove the robots instead of the file's paths. It now overrides that one, with one
#      action per robot: W for a robot whose path is used up (or missing), where the old one
#      returned a shorter vector and so failed the step with "incorrect vector size".
#      DummyPlanner's initialize is the base class's, which does nothing, so nothing else runs.
#  (2) The default --planTimeLimit is INT_MAX seconds, and waiting that long on the planner's
#      future can overflow on some standard libraries and count every step as a timeout: replay
#      passes 60.
#  (3) Evaluation mode reads the paths under "Planner Paths" while the writer writes
#      "plannerPaths". Fleet writes both keys, so nothing is mended; check_output requires the two
#      to be equal. It also requires what the loader would take silently: without that key every
#      robot just waits, and letters other than F, R, C and W are dropped, shifting the path.
#  (4) Evaluation mode saved no results. The added option --evaluationOutput FILE saves them
#      there, in the usual format, so AllValid, numTaskFinished and errors can be read.
if ! (cd "$work/startkit" && patch -p1 --no-backup-if-mismatch --quiet) >"$work/patch.log" 2>&1 <<'PATCH'
--- a/inc/Evaluation.h
+++ b/inc/Evaluation.h
@@ -16,6 +16,6 @@
 
     void load_plans(std::string fname);
 
-    virtual std::vector<Action> plan(int time_limit);
+    void plan(int time_limit, std::vector<Action>& actions) override;
 
 };
--- a/src/Evaluation.cpp
+++ b/src/Evaluation.cpp
@@ -39,16 +39,15 @@
 }
 
 
-std::vector<Action> DummyPlanner::plan(int time_limit)
+void DummyPlanner::plan(int time_limit, std::vector<Action>& actions)
 {
-    std::vector<Action> result;
-    for (auto & dq: agent_plans)
+    actions.assign(env->num_of_agents, Action::W);
+    for (size_t k = 0; k < agent_plans.size() && k < actions.size(); ++k)
     {
-        if (!dq.empty())
+        if (!agent_plans[k].empty())
         {
-            result.push_back(dq.front());
-            dq.pop_front();
+            actions[k] = agent_plans[k].front();
+            agent_plans[k].pop_front();
         }
     }
-    return result;
 }
--- a/src/driver.cpp
+++ b/src/driver.cpp
@@ -50,6 +50,7 @@
         ("output,o", po::value<std::string>()->default_value("./test.json"), "output file name")
         ("outputScreen", po::value<int>()->default_value(1), "the level of details in the output file, 1--showing all the output, 2--ignore the events and tasks, 3--ignore the events, tasks, errors, planner times, starts and paths")
         ("evaluationMode", po::value<bool>()->default_value(false), "evaluate an existing output file")
+        ("evaluationOutput", po::value<std::string>()->default_value(""), "in evaluation mode, the file the replay's results are saved to")
         ("simulationTime", po::value<int>()->default_value(5000), "run simulation")
         ("fileStoragePath", po::value<std::string>()->default_value(""), "the path to the storage path")
         ("planTimeLimit", po::value<int>()->default_value(INT_MAX), "the time limit for planner in seconds")
@@ -164,6 +165,10 @@
     {
         system_ptr->saveResults(vm["output"].as<std::string>(),vm["outputScreen"].as<int>());
     }
+    else if (!vm["evaluationOutput"].as<std::string>().empty())
+    {
+        system_ptr->saveResults(vm["evaluationOutput"].as<std::string>(),vm["outputScreen"].as<int>());
+    }
 
     delete model;
     delete logger;
PATCH
then
  cat "$work/patch.log" >&2
  fail "the mends do not apply to $kit (is it the 2023-archive Start-Kit?)"
fi

build_start=$SECONDS
cmake -S "$work/startkit" -B "$work/startkit/build" -DCMAKE_BUILD_TYPE=Release >"$work/configure.log" 2>&1 ||
  { tail -n 30 "$work/configure.log" >&2; fail "configuring the Start-Kit failed (Boost program_options, system, filesystem, log, log_setup: scripts/install-deps); log $work/configure.log"; }
cmake --build "$work/startkit/build" -j2 >"$work/build.log" 2>&1 ||
  { tail -n 40 "$work/build.log" >&2; fail "building the Start-Kit failed; log $work/build.log"; }
lifelong="$work/startkit/build/lifelong"
[ -x "$lifelong" ] || fail "the Start-Kit build made no $lifelong"
echo "Start-Kit built in $((SECONDS - build_start)) s"

# --- Checks -------------------------------------------------------------------------------------
# check_output FILE INSTANCE: FILE is a Start-Kit output that a replay can read: valid by Fleet's
# own account, one path per robot of the instance, each of $steps actions F, R, C or W, and the
# same paths under "plannerPaths" and "Planner Paths".
check_output() {
  python3 - "$1" "$2" "$steps" <<'PY'
import json, re, sys
path, instance, steps = sys.argv[1], sys.argv[2], int(sys.argv[3])
def fail(msg):
    print(f"{path}: {msg}", file=sys.stderr)
    sys.exit(1)
try:
    out = json.load(open(path))
except (OSError, ValueError) as e:
    fail(f"not a JSON file: {e}")
team = json.load(open(instance))["teamSize"]
for key in ("actionModel", "AllValid", "teamSize", "start", "numTaskFinished", "sumOfCost", "makespan",
            "actualPaths", "plannerPaths", "plannerTimes", "errors", "events", "tasks", "Planner Paths"):
    if key not in out:
        fail(f'no key "{key}"')
if out["actionModel"] != "MAPF_T":
    fail(f'actionModel is {out["actionModel"]!r}, not "MAPF_T"')
if out["teamSize"] != team:
    fail(f'teamSize {out["teamSize"]}, the instance {instance} has {team}')
if out["AllValid"] != "Yes" or out["errors"]:
    fail(f'Fleet itself reports AllValid {out["AllValid"]!r}, errors {out["errors"][:5]}')
if out["Planner Paths"] != out["plannerPaths"]:
    fail('"Planner Paths" differs from "plannerPaths"')
paths = out["Planner Paths"]
if len(paths) != team:
    fail(f'{len(paths)} paths under "Planner Paths" for {team} robots')
action = re.compile(r"^[FRCW]$")
for i, p in enumerate(paths):
    acts = p.split(",") if p else []
    if len(acts) != steps or not all(action.match(a) for a in acts):
        bad = [a for a in acts if not action.match(a)][:3]
        fail(f"robot {i}'s path has {len(acts)} actions for {steps} steps"
             + (f", and ones the Start-Kit does not know: {bad}" if bad else ""))
PY
}

# check_replay FILE REPLAY: the Start-Kit's replay of FILE found every step valid and finished
# the tasks FILE says, at the same steps, with every robot moving as FILE says.
check_replay() {
  python3 - "$1" "$2" <<'PY'
import json, sys
path, replay_path = sys.argv[1], sys.argv[2]
out, replay = json.load(open(path)), json.load(open(replay_path))
problems = []
if replay["AllValid"] != "Yes":
    problems.append(f'AllValid is {replay["AllValid"]!r}')
if replay["errors"]:
    problems.append(f'{len(replay["errors"])} errors, the first ones [robot, other robot, step, what]: {replay["errors"][:5]}')
if replay["numTaskFinished"] != out["numTaskFinished"]:
    problems.append(f'{replay["numTaskFinished"]} tasks finished, {path} says {out["numTaskFinished"]}')
moved = [i for i, (a, b) in enumerate(zip(replay["actualPaths"], out["actualPaths"])) if a != b]
if moved or len(replay["actualPaths"]) != len(out["actualPaths"]):
    problems.append(f'the actual paths of robots {moved[:10]} differ from the ones in {path}')
def finishes(o):
    return [sorted(e[1] for e in evs if e[2] == "finished") for evs in o["events"]]
late = [i for i, (a, b) in enumerate(zip(finishes(replay), finishes(out))) if a != b]
if late:
    i = late[0]
    problems.append(f'robots {late[:10]} finish tasks at other steps; robot {i}: replay {finishes(replay)[i][:8]}, '
                    f'{path} {finishes(out)[i][:8]}')
if problems:
    print(f"the replay {replay_path} of {path}:\n  " + "\n  ".join(problems), file=sys.stderr)
    sys.exit(1)
print(f'{replay["numTaskFinished"]} tasks finished, every step valid, sumOfCost {replay["sumOfCost"]} '
      f'(Fleet: {out["sumOfCost"]})')
PY
}

# replay FILE INSTANCE: runs the mended Start-Kit's evaluation mode on FILE; results in FILE.replay.json.
replay() {
  rm -f "$1.replay.json"
  local status=0
  "$lifelong" --inputFile "$2" --output "$1" --evaluationMode true --evaluationOutput "$1.replay.json" \
    --simulationTime "$steps" --planTimeLimit 60 >"$1.replay.log" 2>&1 || status=$?
  [ $status -eq 0 ] ||
    { tail -n 20 "$1.replay.log" >&2; fail "the Start-Kit's replay of $1 exited $status; log $1.replay.log"; }
  [ -s "$1.replay.json" ] || fail "the Start-Kit's replay of $1 wrote no $1.replay.json; log $1.replay.log"
}

# fleet_case NAME INSTANCE [MAPF-EVAL OPTIONS...]: Fleet's run, then its replay.
fleet_case() {
  local name=$1 instance=$2
  shift 2
  local out="$work/$name.json"
  local start=$SECONDS
  "$fleetctl" mapf-eval --instance "$instance" --steps "$steps" --seed 1 --output "$out" --json "$@" \
    >"$work/$name.stdout" 2>"$work/$name.stderr" ||
    { cat "$work/$name.stdout" "$work/$name.stderr" | tail -n 20 >&2
      fail "$name: fleetctl mapf-eval --instance $instance $* exited non-zero (output $work/$name.stdout, $work/$name.stderr)"; }
  check_output "$out" "$instance" || fail "$name: fleetctl mapf-eval wrote an output the Start-Kit cannot replay"
  replay "$out" "$instance"
  local summary
  summary=$(check_replay "$out" "$out.replay.json") || fail "$name: the Start-Kit does not accept Fleet's run"
  echo "$name: $summary ($((SECONDS - start)) s)"
}

fleet_case random_100 "$random_instance"
fleet_case random_100_delays "$random_instance" --delay 0.01,2,8
fleet_case warehouse_small_60 "$warehouse_instance"
fleet_case random_100_window_search_delays "$random_instance" --lns-window 6 --delay 0.01,2,8

# The replay can fail: robot 0 of the first case drives forward at every step. 200 steps straight
# on leave a 32 x 32 map, so it must hit an obstacle, another robot or the map's edge, and the
# first error must name it.
bad="$work/random_100_forward.json"
python3 - "$work/random_100.json" "$bad" "$steps" <<'PY'
import json, sys
out = json.load(open(sys.argv[1]))
forward = ",".join(["F"] * int(sys.argv[3]))
out["plannerPaths"][0] = out["Planner Paths"][0] = forward
json.dump(out, open(sys.argv[2], "w"), indent=4)
PY
replay "$bad" "$random_instance"
python3 - "$bad" "$bad.replay.json" <<'PY' || fail "the Start-Kit accepted $bad, where robot 0 only drives forward"
import json, sys
replay = json.load(open(sys.argv[2]))
errors = replay["errors"]
if replay["AllValid"] != "No" and not errors:
    print(f"{sys.argv[2]}: AllValid {replay['AllValid']!r} and no errors", file=sys.stderr)
    sys.exit(1)
first = errors[0] if errors else None
if first is not None and 0 not in first[:2]:
    print(f"{sys.argv[2]}: the first error {first} is not robot 0's", file=sys.stderr)
    sys.exit(1)
print(f"robot 0 driven straight on: AllValid {replay['AllValid']}, first error {first}")
PY
echo "startkit_replay_test: ok"
