// fleetctl map check|sample|render: wiring only; the work is done in core/map (and
// core/coordination for grid sites).

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "cli/command_flags.hpp"
#include "commands.hpp"
#include "coordination/grid_map.hpp"
#include "map/reference_samples.hpp"
#include "map/site_map.hpp"
#include "map/svg_render.hpp"
#include "monitor/track_recorder.hpp"

namespace fleet::cli {

namespace {

/// A site given by path, or by name as maps/NAME.yaml under the project root (InputError naming
/// it and listing the sites when there is no such name).
std::string resolve_site(const CommandArgs& args, const std::string& site) {
  if (std::filesystem::exists(site) || site.find('/') != std::string::npos || site.ends_with(".yaml")) return site;
  return known_site_path(args.source_dir, site);
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

/// Prints a road network's warnings; with --strict they make it unusable.
bool warnings_pass(const std::vector<std::string>& warnings, bool strict, std::ostream& err) {
  for (const std::string& w : warnings) err << (strict ? "error (--strict): " : "warning: ") << w << "\n";
  return !strict || warnings.empty();
}

/// A grid site (MovingAI .map): its size, free cells, components and dead ends.
int check_grid(const std::string& path, std::ostream& out, std::ostream& err, std::string& json) {
  if (json.size() > 1) json += ",";
  try {
    const coordination::GridReport report = coordination::check_grid_map(coordination::load_grid_map(path));
    out << coordination::format_grid_report(report, path);
    json += "{\"site\":\"" + json_escape(path) +
            "\",\"usable\":true,\"kind\":\"grid\",\"rows\":" + std::to_string(report.rows) +
            ",\"cols\":" + std::to_string(report.cols) + ",\"free_cells\":" + std::to_string(report.free_cells) +
            ",\"components\":" + std::to_string(report.components) +
            ",\"largest_component\":" + std::to_string(report.largest_component) +
            ",\"dead_ends\":" + std::to_string(report.dead_ends) + "}";
    return kExitOk;
  } catch (const InputError& e) {
    err << e.what() << "\n";
    json += "{\"site\":\"" + json_escape(path) + "\",\"usable\":false,\"error\":\"" + json_escape(e.what()) + "\"}";
    return kExitBadInput;
  }
}

int check(const CommandArgs& args, const std::vector<std::string>& words, std::ostream& out, std::ostream& err) {
  const auto flags = flags_or_report("map", "check", words, err);
  if (!flags) return kExitBadInput;
  const std::vector<std::string>& sites = flags->positionals();
  const bool strict = flags->flag("strict");
  if (sites.empty()) {
    err << "map check: name a site\n" << flags->usage();
    return kExitBadInput;
  }
  int code = kExitOk;
  std::string json = "[";
  for (const std::string& name : sites) {
    if (name.ends_with(".xodr")) {
      err << "map check: " << name << " is an OpenDRIVE road network; map check reads a site file (SITE.yaml or a "
          << "site name), which names its network under 'opendrive'. To read the network alone: fleetctl map sample "
          << name << "\n";
      code = kExitBadInput;
      continue;
    }
    if (name.ends_with(".map")) {
      code = std::max(code, check_grid(name, out, err, json));
      continue;
    }
    const std::string path = resolve_site(args, name);
    bool usable = false;
    try {
      const map::SiteMap site = map::load_site_map_unchecked(path);
      const map::SiteReport report = map::check_site_map(site);
      out << map::format_report(report);
      for (const std::string& p : report.problems) err << p << "\n";
      usable = warnings_pass(site.network.warnings, strict, err) && report.usable();
      if (json.size() > 1) json += ",";
      json += "{\"site\":\"" + json_escape(path) + "\",\"usable\":" + (usable ? "true" : "false") +
              ",\"roads\":" + std::to_string(report.roads) + ",\"points\":" + std::to_string(report.points) +
              ",\"edges\":" + std::to_string(report.edges) +
              ",\"components\":" + std::to_string(report.weak_components) + "}";
    } catch (const std::exception& e) {  // map::MapError, or InputError for an unknown site name
      err << e.what() << "\n";
      if (json.size() > 1) json += ",";
      json += "{\"site\":\"" + json_escape(path) + "\",\"usable\":false,\"error\":\"" + json_escape(e.what()) + "\"}";
    }
    if (!usable) code = kExitBadInput;
  }
  if (args.json) out << json << "]\n";
  return code;
}

int sample(const CommandArgs& args, const std::vector<std::string>& rest, std::ostream& out, std::ostream& err) {
  const auto flags = flags_or_report("map", "sample", rest, err);
  if (!flags) return kExitBadInput;
  const double step = flags->number("step").value_or(1.0);
  const auto max_rows = static_cast<std::size_t>(flags->integer("max-rows").value_or(map::kDefaultMaxSamples));
  const double tolerance = flags->number("tolerance").value_or(map::kDefaultGeometryTolerance);
  const bool strict = flags->flag("strict");
  if (flags->positionals().size() != 1) {
    err << "map sample: name one OpenDRIVE file\n" << flags->usage();
    return kExitBadInput;
  }
  const std::string& file = flags->positionals().front();
  try {
    const map::RoadNetwork network = map::load_opendrive(file, tolerance);
    if (!warnings_pass(network.warnings, strict, err)) return kExitBadInput;
    // Rows are written as they are made: memory does not grow with the roads' length.
    // The header goes out with the first row: a bad step or too many rows print nothing.
    bool first = true;
    map::for_each_reference_sample(network, step, max_rows, [&](const map::ReferenceSample& sample) {
      if (!args.json) {
        if (first) map::write_samples_csv_header(out);
        first = false;
        map::write_sample_csv(sample, out);
        return;
      }
      out << (first ? "[" : ",")
          << nlohmann::json{{"road_id", sample.road_id},
                            {"s", sample.s},
                            {"x", sample.x},
                            {"y", sample.y},
                            {"hdg", sample.hdg}}
                 .dump();
      first = false;
    });
    if (args.json) out << (first ? "[" : "") << "]\n";
    if (!args.json && first) map::write_samples_csv_header(out);
  } catch (const map::MapError& e) {
    err << e.what() << "\n";
    return kExitBadInput;
  }
  return kExitOk;
}

int render(const CommandArgs& args, const std::vector<std::string>& rest, std::ostream& out, std::ostream& err) {
  const auto flags = flags_or_report("map", "render", rest, err);
  if (!flags) return kExitBadInput;
  map::RenderOptions options;
  options.graph_points = !flags->flag("no-points");
  const std::string output = flags->value("o").value_or("");
  const std::string tracks_file = flags->value("tracks").value_or("");
  const double since = flags->number("since").value_or(-std::numeric_limits<double>::infinity());
  if (flags->positionals().size() != 1 || output.empty()) {
    err << "map render: name one site and -o FILE.svg\n" << flags->usage();
    return kExitBadInput;
  }
  const std::string& site = flags->positionals().front();
  if (!tracks_file.empty()) {
    // Tracks a soak wrote beside a deadlock or collision report (TrackRecorder's CSV).
    std::ifstream in(tracks_file);
    if (!in) {
      err << "map render: " << tracks_file << ": cannot read\n";
      return kExitBadInput;
    }
    try {
      for (auto& t : monitor::read_tracks_csv(in, tracks_file)) {
        map::RenderTrack r{t.robot_id, {}, {}};
        for (std::size_t k = 0; k < t.poses.size(); ++k) {
          if (t.sim_s[k] < since) continue;
          r.times.push_back(t.sim_s[k]);
          r.poses.push_back(t.poses[k]);
        }
        if (!r.poses.empty()) options.tracks.push_back(std::move(r));
      }
    } catch (const std::runtime_error& e) {
      err << "map render: " << e.what() << "\n";
      return kExitBadInput;
    }
  }
  try {
    const map::SiteMap m = map::load_site_map_unchecked(resolve_site(args, site));
    std::ofstream file(output);
    file << map::render_svg(m, options);
    if (!file) {
      err << output << ": cannot write\n";
      return kExitFailed;
    }
  } catch (const map::MapError& e) {
    err << e.what() << "\n";
    return kExitBadInput;
  }
  out << (args.json ? nlohmann::json{{"wrote", output}}.dump() : "wrote " + output) << "\n";
  return kExitOk;
}

}  // namespace

int map_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
  constexpr const char* kSubcommands = "check, sample, render (list and set ask the server)";
  if (args.args.empty()) {
    err << "map needs a subcommand: " << kSubcommands << "\n";
    return kExitBadInput;
  }
  const std::string& sub = args.args.front();
  const std::vector<std::string> rest(args.args.begin() + 1, args.args.end());
  if (sub == "check") return check(args, rest, out, err);
  if (sub == "sample") return sample(args, rest, out, err);
  if (sub == "render") return render(args, rest, out, err);
  err << "map: unknown subcommand '" << sub << "' (" << kSubcommands << ")\n";
  return kExitBadInput;
}

}  // namespace fleet::cli
