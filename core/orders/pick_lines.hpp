#pragma once
// Pick orders by lines, as a warehouse management system sends them: which article, how many
// boxes, from which rack place. The lines are checked whole against what the places hold before
// anything is stored, then cut into tours a picker drives in one go.

#include <map>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "map/site.hpp"

namespace fleet::config {
struct FleetConfig;
}

namespace fleet::orders {

/// One line of a pick list: `quantity` boxes of `item` from the rack place `place`.
struct PickLine {
  std::string place;
  std::string item;
  int quantity = 0;
  int line = 0;  ///< 1-based line of the file it came from, for messages
};

/// Reads a pick list in CSV: `place,item,quantity` per line, an optional header line naming
/// those columns, blank lines and `#` comments skipped. Throws InputError naming
/// `source:line` and the field for a line it cannot read (a missing field, a quantity that is
/// not a whole number >= 1), or when there is no line at all.
std::vector<PickLine> parse_pick_lines(std::string_view text, const std::string& source);
/// `lines` as parse_pick_lines reads them: place,item,quantity per line.
std::string pick_lines_csv(const std::vector<PickLine>& lines);

/// The first problem of `lines`, naming `source:line`, or nothing when every line can be
/// picked: the place is known (`places`, with the closest names otherwise) and has boxes
/// (`stock`, what is left of each place's boxes), of the line's item, as many as all the lines
/// on that place ask for together, and no heavier than `max_box_mass` kg (what the pickers'
/// grippers hold).
std::optional<std::string> check_pick_lines(const std::vector<PickLine>& lines, const std::vector<std::string>& places,
                                            const std::map<std::string, map::BoxStock>& stock, double max_box_mass,
                                            const std::string& source);

/// The boxes the site declares on its places, by place.
std::map<std::string, map::BoxStock> declared_boxes(const map::Site& site);
/// The heaviest box a fleet that performs pickItem holds (its load's max_mass), kg; 0 without one.
double max_pickable_mass(const config::FleetConfig& config);
/// The site's place poses, for plan_tours.
std::map<std::string, geometry::Pose2> place_poses(const map::Site& site);

/// Two places of one rack row (one face of a rack along one lane): their poses 5 cm apart or
/// less across the row.
bool same_rack_row(const geometry::Pose2& a, const geometry::Pose2& b);

/// Boxes a picker carries on one tour: the two slots of its tray (robot::PickerArmLayout).
inline constexpr int kTourBoxes = 2;
/// Boxes a loader sets on one transporter's pallet: the row behind its base the arm reaches,
/// three across, two layers high (robot::PickerArmLayout::deck; server.loader_pallet_boxes).
inline constexpr int kLoaderPalletBoxes = 6;
/// Boxes of an automatic loader walk: one pallet.
inline constexpr int kLoaderWalkBoxes = kLoaderPalletBoxes;

/// A picker's round: lines picked one after the other, then dropped together.
struct PickTour {
  std::vector<PickLine> lines;  ///< in the order the picker visits them
  int boxes() const;
};

/// Cuts checked lines into tours of at most `capacity` boxes (what a picker carries). Lines on
/// one place are merged first; places are visited along the aisles: ordered by where a picker
/// stands to reach them (the place's y, then x, from `poses`), so each tour keeps to the aisles
/// its boxes come from. A line larger than the capacity is split over several tours.
std::vector<PickTour> plan_tours(const std::vector<PickLine>& lines, int capacity,
                                 const std::map<std::string, geometry::Pose2>& poses);

/// A random pick list, as the automatic orders place one for a free picker: a place with boxes
/// left in `stock`, no heavier than `max_box_mass` kg, and between one box and `capacity` of
/// them; further lines from other places of the same rack row (the same y in `poses`, so the
/// tour stays in one aisle) while the boxes leave room, so that they fill `capacity` unless the
/// row runs out of boxes. Nothing when no place has a box to give.
std::optional<std::vector<PickLine>> choose_auto_pick_list(const std::map<std::string, map::BoxStock>& stock,
                                                           const std::map<std::string, geometry::Pose2>& poses,
                                                           double max_box_mass, int capacity, std::mt19937_64& rng);

}  // namespace fleet::orders
