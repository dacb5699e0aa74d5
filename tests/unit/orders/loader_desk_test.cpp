// The server's loader desk on the plant: the transports a loader job asks for, the updates it
// sends its robots as they report, and how the job ends (docs/loader.md).
#include "orders/loader_desk.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "map/site_map.hpp"
#include "orders/order_intake.hpp"
#include "test_paths.hpp"

namespace fleet::orders {
namespace {

std::vector<const Order*> transports_of(const OrderBook& book, std::int64_t pick) {
  std::vector<const Order*> out;
  for (const auto& [id, o] : book.all()) {
    if (o.kind == OrderKind::kTransport && o.caused_by == std::vector<std::int64_t>{pick}) out.push_back(&o);
  }
  return out;
}

// The plant's site, its pallets where they stand at the start, and a book and robots the test
// moves on as the server and the agents would.
struct Plant {
  map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/plant.yaml"));
  AreaLedger ledger;
  OrderBook book;
  std::map<std::string, RobotEntry> robots;
  // Three boxes a pallet: a short list fills more than one.
  LoaderDesk desk{{.pallet_boxes = 3, .transporter_fleet = "stackers"}};

  Plant() {
    std::vector<Place> places;
    for (const auto& area : site.site.loading_areas) places.push_back({area.id, area.pose});
    ledger = AreaLedger(places);
    int id = 1;
    for (const auto& area : site.site.loading_areas) {
      if (area.pallet_at_start)
        ledger.record({.id = id++, .kind = "pallet", .pose = area.pose, .place = area.id, .carried_by = ""});
    }
  }

  std::vector<LoaderAction> step() {
    auto actions = desk.step({.book = book, .robots = robots, .site = site.site, .ledger = ledger});
    // The server's part: the transports into the book, the revisions onto the orders.
    for (const LoaderAction& action : actions) {
      if (action.kind == LoaderAction::Kind::kCreate) {
        desk.transport_created(book.create(action.draft, 0.0));
      } else {
        book.revise(action.order_id, action.revision, {});
      }
    }
    return actions;
  }

  RobotEntry& robot(const std::string& id, const std::string& fleet) {
    RobotEntry& entry = robots[id];
    entry.id = id;
    entry.fleet_id = fleet;
    entry.registered = true;
    entry.last.robot_id = id;
    return entry;
  }

  /// The desk asks for the first pallet of walk `pick`, and stacker `robot` takes that transport:
  /// its id.
  std::int64_t stacker_takes_the_first_pallet(std::int64_t pick, const std::string& robot) {
    step();
    const std::int64_t transport = transports_of(book, pick).at(0)->id;
    this->robot(robot, "stackers");
    EXPECT_EQ(book.assign(transport, robot, 0.0), TransitionResult::kApplied);
    step();
    return transport;
  }

  /// A transporter standing with its pallet where its order sends it.
  void holds_at_stand(const Order& transport) {
    RobotEntry& s = robots.at(transport.robot_id);
    s.last.task_state = "HOLDING";
    s.last.pose = *transport.stand;
  }
};

/// A pick order worked as a loader walk starting at RB2.
Order walk_draft(const std::string& lines) {
  Order draft;
  draft.kind = OrderKind::kPick;
  draft.loader = true;
  draft.pick_area = "RB2";
  draft.lines = lines;
  return draft;
}

TEST(LoaderDesk, PicksAListOntoTwoPalletsAndSendsEachToExpedition) {
  Plant plant;
  // Four boxes at two rack places: three fill the first pallet, the fourth goes on the second.
  const Order draft = walk_draft("RB2,A2,2\nRB3,A3,1\nRB3,A3,1\n");
  const std::int64_t pick = plant.book.create(draft, 0.0).id;
  plant.robot("picker1", "pickers");
  ASSERT_EQ(plant.book.assign(pick, "picker1", 0.0), TransitionResult::kApplied);

  // The picker has it: the job asks for a transporter with an empty pallet from a PK place.
  auto actions = plant.step();
  ASSERT_EQ(actions.size(), 1u);
  ASSERT_EQ(actions[0].kind, LoaderAction::Kind::kCreate);
  auto transports = transports_of(plant.book, pick);
  ASSERT_EQ(transports.size(), 1u);
  const std::int64_t first = transports[0]->id;
  EXPECT_EQ(transports[0]->pick_area, "PK1");
  EXPECT_TRUE(transports[0]->drop_area.empty());
  EXPECT_EQ(transports[0]->fleet_id, "stackers");
  EXPECT_TRUE(transports[0]->loader);
  // Asked once: no second transport while the first waits for a robot. Its full pallet has a
  // place kept at expedition from now on.
  plant.step();
  EXPECT_EQ(transports_of(plant.book, pick).size(), 1u);
  EXPECT_EQ(plant.desk.reserved_places(), (std::set<std::string>{"EX1"}));

  // A stacker takes it: sent to stand behind the picker's first stop. The four boxes do not fit
  // its pallet, but the next transporter is asked for only once this one leaves.
  plant.robot("stacker1", "stackers");
  ASSERT_EQ(plant.book.assign(first, "stacker1", 0.0), TransitionResult::kApplied);
  plant.step();
  const Order& t1 = *plant.book.find(first);
  ASSERT_TRUE(t1.stand.has_value());
  const geometry::Pose2 rb2 = plant.site.site.find_area("RB2")->pose;
  const LoaderLayout layout;
  const geometry::Pose2 expected =
      transporter_pose(picker_stop_pose(rb2, layout.item_standoff), layout.deck_x, layout.pallet_x);
  EXPECT_NEAR(t1.stand->x, expected.x, 1e-9);
  EXPECT_NEAR(t1.stand->y, expected.y, 1e-9);
  EXPECT_EQ(transports_of(plant.book, pick).size(), 1u);

  // Nothing is released before the transporter stands behind the stop.
  RobotEntry& picker = plant.robots.at("picker1");
  picker.last.order_id = pick;
  picker.last.walk_stop = 0;
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->released_stops, 0u);
  plant.holds_at_stand(t1);
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->released_stops, 1u);
  EXPECT_EQ(plant.book.find(pick)->pallet, static_cast<int>(first));

  // Two boxes on the pallet: the transporter follows to RB3, where the third is released once it
  // stands there.
  picker.last.walk_stop = -1;
  picker.last.boxes_loaded = 2;
  plant.step();
  const geometry::Pose2 behind_rb2 = *plant.book.find(first)->stand;
  EXPECT_GT(geometry::distance(behind_rb2.position(), expected.position()), 1.0);
  picker.last.walk_stop = 1;
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->released_stops, 1u);
  plant.holds_at_stand(*plant.book.find(first));
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->released_stops, 2u);

  // The pallet is full: it goes to a free expedition place, and the next transporter is asked
  // for, from the next free PK place; the picker has no pallet behind it meanwhile.
  picker.last.boxes_loaded = 3;
  picker.last.walk_stop = -1;
  plant.step();
  EXPECT_EQ(plant.book.find(first)->drop_area, "EX1");
  EXPECT_FALSE(plant.book.find(first)->stand.has_value());
  EXPECT_EQ(plant.book.find(pick)->pallet, 0);
  transports = transports_of(plant.book, pick);
  ASSERT_EQ(transports.size(), 2u);
  const std::int64_t second = transports[1]->id;
  EXPECT_EQ(transports[1]->pick_area, "PK4");  // PK1 is promised to the first
  plant.robot("stacker2", "stackers");
  ASSERT_EQ(plant.book.assign(second, "stacker2", 0.0), TransitionResult::kApplied);
  plant.step();
  ASSERT_TRUE(plant.book.find(second)->stand.has_value());
  EXPECT_EQ(plant.book.find(pick)->released_stops, 2u);
  plant.holds_at_stand(*plant.book.find(second));
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->released_stops, 3u);
  EXPECT_EQ(plant.book.find(pick)->pallet, static_cast<int>(second));

  // The walk ends at its last stop (the picker's order DONE): the second pallet leaves too.
  ASSERT_EQ(plant.book.transition(pick, OrderStatus::kDone, 0.0), TransitionResult::kApplied);
  picker.last = {};
  plant.step();
  EXPECT_EQ(plant.book.find(second)->drop_area, "EX3");  // EX2 holds a pallet, EX1 is promised
  EXPECT_EQ(plant.desk.reserved_places(), (std::set<std::string>{"EX1", "EX3"}));
  const LoaderJob* job = plant.desk.job_of(pick);
  ASSERT_NE(job, nullptr);
  EXPECT_EQ(job->boxes_loaded(), 4);
  ASSERT_EQ(job->runs().size(), 2u);
  EXPECT_EQ(job->runs()[0].boxes, 3);
  EXPECT_EQ(job->runs()[1].boxes, 1);

  // Both delivered: the job is over.
  for (const std::int64_t t : {first, second}) {
    ASSERT_EQ(plant.book.set_phase(t, OrderPhase::kToDrop, 0.0), TransitionResult::kApplied);
    ASSERT_EQ(plant.book.transition(t, OrderStatus::kDone, 0.0), TransitionResult::kApplied);
  }
  plant.step();
  EXPECT_EQ(plant.desk.job_of(pick), nullptr);
}

// A pallet is not fetched for a walk before expedition has a place for it once full: a full
// pallet with nowhere to go would stand in its rack lane, closed behind it, for as long.
TEST(LoaderDesk, APalletIsFetchedOnlyWithAnExpeditionPlaceKeptForIt) {
  Plant plant;
  int id = 1000;
  for (const std::string& place : plant.site.site.packing->full_pallets_to) {
    if (!plant.ledger.holds_load(place)) {
      plant.ledger.record({.id = id++, .kind = "pallet", .pose = {}, .place = place, .carried_by = ""});
    }
  }
  const std::int64_t pick = plant.book.create(walk_draft("RB2,A2,2\n"), 0.0).id;
  const std::int64_t other = plant.book.create(walk_draft("RB3,A3,2\n"), 0.0).id;
  plant.step();
  EXPECT_TRUE(transports_of(plant.book, pick).empty()) << "every expedition place holds a pallet";
  // EX1 and EX3 come free: the two walks, asking in one look, take one each, and empty pallets
  // from two PK places.
  plant.ledger.record({.id = 1000, .kind = "pallet", .pose = {}, .place = "PS1", .carried_by = ""});
  plant.ledger.record({.id = 1001, .kind = "pallet", .pose = {}, .place = "PS2", .carried_by = ""});
  plant.step();
  plant.step();
  const auto first = transports_of(plant.book, pick);
  const auto second = transports_of(plant.book, other);
  ASSERT_EQ(first.size(), 1u);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_NE(first[0]->pick_area, second[0]->pick_area);
  EXPECT_EQ(plant.desk.reserved_places(), (std::set<std::string>{"EX1", "EX3"}));
}

// A picker whose order fails mid-walk leaves the stops not loaded at their places; the boxes
// already on the pallet go to expedition.
TEST(LoaderDesk, AFailedWalkSendsThePalletItFilledToExpedition) {
  Plant plant;
  const Order draft = walk_draft("RB2,A2,1\nRB3,A3,1\n");
  const std::int64_t pick = plant.book.create(draft, 0.0).id;
  plant.robot("picker1", "pickers");
  plant.book.assign(pick, "picker1", 0.0);
  plant.step();
  const std::int64_t first = transports_of(plant.book, pick).at(0)->id;
  plant.robot("stacker1", "stackers");
  plant.book.assign(first, "stacker1", 0.0);
  plant.step();
  EXPECT_EQ(transports_of(plant.book, pick).size(), 1u);  // two boxes fit one pallet
  plant.holds_at_stand(*plant.book.find(first));
  RobotEntry& picker = plant.robots.at("picker1");
  picker.last.order_id = pick;
  picker.last.walk_stop = 0;
  plant.step();
  picker.last.boxes_loaded = 1;
  picker.last.walk_stop = -1;
  plant.step();
  ASSERT_EQ(plant.book.transition(pick, OrderStatus::kFailed, 0.0, "arm fault"), TransitionResult::kApplied);
  plant.step();
  EXPECT_EQ(plant.book.find(first)->drop_area, "EX1");
  EXPECT_EQ(plant.desk.job_of(pick)->boxes_loaded(), 1);
}

// A loader walk is held back from the pickers until a stacker has taken its first pallet to the
// first stop: the stacker fetches it and drives there while the pickers do other work, and the
// picker, sent then, finds its pallet waiting.
TEST(LoaderDesk, AWalkGoesToAPickerOnceItsFirstPalletStandsAtTheFirstStop) {
  Plant plant;
  const Order draft = walk_draft("RB2,A2,2\n");
  const std::int64_t pick = plant.book.create(draft, 0.0).id;
  const Order tray_pick = [&] {
    Order tray = draft;
    tray.loader = false;
    return plant.book.create(tray, 0.0);
  }();
  plant.step();
  const auto transports = transports_of(plant.book, pick);
  ASSERT_EQ(transports.size(), 1u) << "no pallet asked for a walk no picker has yet";
  const std::int64_t first = transports[0]->id;
  EXPECT_FALSE(plant.desk.ready_for_picker(*plant.book.find(pick)));
  EXPECT_TRUE(plant.desk.ready_for_picker(tray_pick)) << "a tray tour waits for nothing";
  EXPECT_TRUE(plant.desk.ready_for_picker(*transports[0]));
  EXPECT_FALSE(plant.desk.ready_for_picker(plant.book.create(draft, 0.0)))
      << "a walk the desk has not looked at yet waits too";

  plant.robot("stacker1", "stackers");
  ASSERT_EQ(plant.book.assign(first, "stacker1", 0.0), TransitionResult::kApplied);
  plant.step();
  ASSERT_TRUE(plant.book.find(first)->stand.has_value()) << "the stacker goes ahead to the first stop";
  EXPECT_EQ(plant.desk.partners(), (std::map<std::string, std::string>{{"stacker1", ""}}))
      << "its lane closes behind it to every robot until a picker comes";
  ASSERT_EQ(plant.book.set_phase(first, OrderPhase::kPicking, 0.0), TransitionResult::kApplied);
  ASSERT_EQ(plant.book.set_phase(first, OrderPhase::kToDrop, 0.0), TransitionResult::kApplied);
  plant.step();
  EXPECT_FALSE(plant.desk.ready_for_picker(*plant.book.find(pick))) << "the pallet is on the forks, not there yet";
  plant.holds_at_stand(*plant.book.find(first));
  plant.step();
  EXPECT_TRUE(plant.desk.ready_for_picker(*plant.book.find(pick))) << "the pallet stands behind the first stop";

  plant.robot("picker1", "pickers");
  ASSERT_EQ(plant.book.assign(pick, "picker1", 0.0), TransitionResult::kApplied);
  plant.step();
  ASSERT_NE(plant.desk.job_of(pick), nullptr);
  EXPECT_EQ(plant.desk.job_of(pick)->picker_id(), "picker1");
  EXPECT_EQ(plant.book.find(pick)->released_stops, 1u) << "its first stop is released at once";
  EXPECT_EQ(plant.desk.partners(), (std::map<std::string, std::string>{{"stacker1", "picker1"}}));
  EXPECT_EQ(transports_of(plant.book, pick).size(), 1u);
}

TEST(LoaderDesk, APickerFollowsItsPalletMovingUpStraightAheadAndLoadsOnceItStands) {
  Plant plant;
  const std::int64_t pick = plant.book.create(walk_draft("RB2,A2,1\nRB3,A3,1\n"), 0.0).id;
  const std::int64_t transport = plant.stacker_takes_the_first_pallet(pick, "stacker1");
  plant.holds_at_stand(*plant.book.find(transport));
  plant.step();
  plant.robot("picker1", "pickers");
  ASSERT_EQ(plant.book.assign(pick, "picker1", 0.0), TransitionResult::kApplied);
  RobotEntry& picker = plant.robots.at("picker1");
  picker.last.order_id = pick;
  picker.last.walk_stop = 0;
  plant.step();
  ASSERT_EQ(plant.book.find(pick)->released_stops, 1u);

  // RB2's box on the pallet: the stacker is sent on to stand behind RB3, 3.5 m on along its line.
  picker.last.boxes_loaded = 1;
  plant.step();
  const geometry::Pose2 behind_rb2 = plant.robots.at("stacker1").last.pose;
  const geometry::Pose2 behind_rb3 = *plant.book.find(transport)->stand;
  ASSERT_TRUE(moving_up_straight(behind_rb2, behind_rb3, behind_rb3, 0.5));
  EXPECT_EQ(plant.book.find(pick)->approach_stops, 0u) << "the stacker stands where it was";
  RobotEntry& stacker = plant.robots.at("stacker1");
  stacker.last.task_state = "RUNNING";
  stacker.last.pose = {behind_rb2.x + 0.2 * std::cos(behind_rb2.yaw), behind_rb2.y + 0.2 * std::sin(behind_rb2.yaw),
                       behind_rb2.yaw};
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->approach_stops, 0u) << "hardly left its stand";
  stacker.last.pose = {behind_rb2.x + 1.0 * std::cos(behind_rb2.yaw), behind_rb2.y + 1.0 * std::sin(behind_rb2.yaw),
                       behind_rb2.yaw};
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->approach_stops, 2u) << "on its way: the picker follows it to RB3";
  EXPECT_EQ(plant.book.find(pick)->released_stops, 1u) << "but loads there only once the pallet stands";
  picker.last.walk_stop = 1;
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->approach_stops, 2u);
  plant.holds_at_stand(*plant.book.find(transport));
  plant.step();
  EXPECT_EQ(plant.book.find(pick)->released_stops, 2u);
  EXPECT_EQ(plant.book.find(pick)->approach_stops, 0u);
}

TEST(LoaderDesk, APalletMovingUpAnyOtherWayIsNotFollowed) {
  const geometry::Pose2 from{10.0, 5.0, 0.0};
  EXPECT_TRUE(moving_up_straight(from, {13.5, 5.0, 0.0}, {11.0, 5.1, 0.0}, 0.5));
  EXPECT_FALSE(moving_up_straight(from, {6.5, 5.0, 0.0}, {9.0, 5.0, 0.0}, 0.5)) << "backwards";
  EXPECT_FALSE(moving_up_straight(from, {13.5, 6.0, 0.0}, {11.0, 5.2, 0.0}, 0.5)) << "to another line";
  EXPECT_FALSE(moving_up_straight(from, {13.5, 5.0, 1.57}, {11.0, 5.0, 0.0}, 0.5)) << "turned";
  EXPECT_FALSE(moving_up_straight(from, {13.5, 5.0, 0.0}, {11.0, 6.0, 0.0}, 0.5)) << "off its line, going round";
  EXPECT_FALSE(moving_up_straight(from, {13.5, 5.0, 0.0}, {10.3, 5.0, 0.0}, 0.5)) << "not yet on its way";
}

// A desk started on a book with a walk under way (a restarted server, a standby that took over)
// takes on the walk's transport: the stacker bringing its pallet is not left standing in the rack
// lane, and no second pallet is fetched.
TEST(LoaderDesk, ADeskStartedAnewTakesOnTheTransportsOfAWalkUnderWay) {
  Plant plant;
  const std::int64_t pick = plant.book.create(walk_draft("RB2,A2,2\n"), 0.0).id;
  const std::int64_t first = plant.stacker_takes_the_first_pallet(pick, "stacker1");
  ASSERT_TRUE(plant.book.find(first)->stand.has_value());

  plant.desk = LoaderDesk({.pallet_boxes = 3, .transporter_fleet = "stackers"});
  plant.step();
  EXPECT_EQ(transports_of(plant.book, pick).size(), 1u) << "no second pallet fetched";
  EXPECT_EQ(plant.desk.partners(), (std::map<std::string, std::string>{{"stacker1", ""}}));
  plant.holds_at_stand(*plant.book.find(first));
  plant.step();
  EXPECT_TRUE(plant.desk.ready_for_picker(*plant.book.find(pick))) << "its pallet stands behind the first stop";
}

// The intake works a pick list as one loader walk when asked, with no drop place; and refuses
// it, naming the field, where the site has no stacker fleet.
TEST(LoaderDesk, IntakeMakesOneLoaderWalkOrRefusesWithoutAStackerFleet) {
  Plant plant;
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  const KnownNames names = known_names(config, plant.site.site);
  const std::map<std::string, std::string> parked;
  IntakeView view{.book = plant.book,
                  .ledger = plant.ledger,
                  .names = names,
                  .site = plant.site.site,
                  .parked_at = parked,
                  .registered = {},
                  .free_robots = {},
                  .reject_when_busy = false,
                  .max_pickable_mass = max_pickable_mass(config),
                  .loader_fleet = loader_fleet(config),
                  .loader_pallet_boxes = 3,
                  .place_distance = {}};
  model::OrderRequest request;
  request.request_id = "r1";
  request.kind = "pick";
  request.lines = "RB3,A3,1\nRB2,A2,2\nRB2,A2,2\n";
  request.handling = "loader";
  const IntakeDecision taken = OrderIntake(view).decide(request);
  ASSERT_TRUE(taken.reply.accepted) << taken.reply.error;
  ASSERT_EQ(taken.drafts.size(), 1u);
  EXPECT_TRUE(taken.drafts[0].loader);
  EXPECT_TRUE(taken.drafts[0].drop_area.empty());
  // Merged by place, cut at three boxes a pallet, in aisle order.
  EXPECT_EQ(taken.drafts[0].lines.substr(0, 4), "RB2,");
  EXPECT_EQ(parse_pick_lines(taken.drafts[0].lines, "walk").size(), 3u);

  view.loader_fleet.clear();
  const IntakeDecision refused = OrderIntake(view).decide(request);
  EXPECT_FALSE(refused.reply.accepted);
  EXPECT_NE(refused.reply.error.find("handling: a loader walk needs a stacker fleet"), std::string::npos)
      << refused.reply.error;
  request.handling = "forks";
  EXPECT_NE(OrderIntake(view).decide(request).reply.error.find("unknown handling 'forks'"), std::string::npos);
}

}  // namespace
}  // namespace fleet::orders
