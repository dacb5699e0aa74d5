"""What bench/figures runs its rows with: the build's binaries and fleetctl on a DDS domain of
its own, Google Benchmark medians, one row per figure, and the page."""

import json
import os
import platform
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class Skipped(Exception):
    """A row whose input data is absent (the shared data beside the checkout)."""


class Runner:
    def __init__(self, build, domain, quick):
        self.bin = os.path.join(build, "bin")
        self.domain = domain
        self.quick = quick
        self.rows = []
        self.failures = 0

    # -- running things ---------------------------------------------------------------------

    def run(self, binary, args, timeout):
        """Runs one of the build's binaries from the project root; returns its stdout. Raises on a
        non-zero exit."""
        print(f"figures: build/bin/{binary} {' '.join(args)}", file=sys.stderr, flush=True)
        started = time.monotonic()
        proc = subprocess.run([os.path.join(self.bin, binary)] + args, cwd=ROOT, capture_output=True,
                              text=True, timeout=timeout)
        print(f"figures:   {time.monotonic() - started:.0f} s, exit {proc.returncode}", file=sys.stderr, flush=True)
        if proc.returncode != 0:
            raise RuntimeError(f"exit {proc.returncode}: {proc.stderr.strip().splitlines()[-1:] or proc.stdout[-200:]}")
        return proc.stdout

    def fleetctl_json(self, args, timeout, accept_exit_1=False):
        """fleetctl --json ARGS on the figures' DDS domain; the last line is the JSON document."""
        argv = ["build/bin/fleetctl", "--domain", str(self.domain), "--json"] + args
        print(f"figures: {' '.join(argv)}", file=sys.stderr, flush=True)
        started = time.monotonic()
        proc = subprocess.run([os.path.join(self.bin, "fleetctl")] + argv[1:], cwd=ROOT, capture_output=True,
                              text=True, timeout=timeout)
        print(f"figures:   {time.monotonic() - started:.0f} s, exit {proc.returncode}", file=sys.stderr, flush=True)
        lines = [line for line in proc.stdout.splitlines() if line.strip()]
        if proc.returncode not in ((0, 1) if accept_exit_1 else (0,)) or not lines:
            raise RuntimeError(f"exit {proc.returncode}: {proc.stderr.strip().splitlines()[-1:]}")
        doc = json.loads(lines[-1])
        if "error" in doc:
            raise RuntimeError(doc["error"])  # fleetctl's own reason, e.g. a tool the run needs is missing
        doc["_exit"] = proc.returncode
        return doc

    def benchmark(self, binary, names, repetitions):
        """Median real time of each named Google Benchmark, in its own unit: {name: (value, unit)}."""
        flt = "^(" + "|".join(names) + ")$"
        out = self.run(binary, [f"--benchmark_filter={flt}", f"--benchmark_repetitions={repetitions}",
                        "--benchmark_report_aggregates_only=true", "--benchmark_format=json"], timeout=900)
        result = {}
        for b in json.loads(out)["benchmarks"]:
            if b.get("aggregate_name") == "median":
                result[b["run_name"]] = (b["real_time"], b["time_unit"])
        missing = [n for n in names if n not in result]
        if missing:
            raise RuntimeError(f"{binary} has no benchmark {', '.join(missing)}")
        return result

    def row(self, what, command, make):
        """Adds one row; `make` returns the figure's text. A failure is reported in the row; a row
        whose data is absent says so and is no failure."""
        try:
            figure = make()
        except Skipped as reason:
            figure = f"skipped: {reason}"
            print(f"figures: {what}: skipped: {reason}", file=sys.stderr, flush=True)
        except Exception as error:  # noqa: BLE001 - any failure is shown in the table and the exit status
            self.failures += 1
            figure = f"**failed**: {error}"
            print(f"figures: {what}: {error}", file=sys.stderr, flush=True)
        self.rows.append((what, figure, command))

    # -- the page -----------------------------------------------------------------------------

    def page(self, started, minutes):
        mode = "`bench/figures --quick`" if self.quick else "`bench/figures`"
        lines = [
            "# Figures",
            "",
            f"<!-- Made by {mode.strip('`')}; re-make the whole page with it, never by hand. -->",
            "",
            f"Every figure below was measured on the commit that last wrote this page, on {started} "
            f"({minutes:.0f} minutes), by "
            f"{mode}, on one machine with {os.cpu_count()} cores ({platform.machine()}, "
            f"{platform.system()} {platform.release()}), one command after another. Each row names the "
            "command that makes it; timings are medians over repetitions. Runs of robots are seeded, and "
            "their results still vary from run to run with thread timing.",
            "",
            "| what | figure | command |",
            "|---|---|---|",
        ]
        for what, figure, command in self.rows:
            lines.append(f"| {what} | {figure} | {command} |")
        return "\n".join(lines) + "\n"


def fmt(value_unit):
    value, unit = value_unit
    unit = {"us": "µs"}.get(unit, unit)
    return f"{value:.3g} {unit}" if value < 100 else f"{value:.0f} {unit}"


def cm(metres):
    return f"{metres * 100:.2f} cm"


def uncommitted_changes():
    """The tracked files that differ from the commit checked out ("" when none, or not a checkout)."""
    try:
        return subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                              capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""
