#include "orders/order_intake.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace fleet::orders {
namespace {

/// A small site: loading areas A1 (a pallet on it), A2 and A3 (empty); parking places H1 to H3;
/// rack places R1 and R2 with boxes of item BX; packing stations PS1 and PS2, each with a pallet
/// that is full at 3 boxes. Forklifts fl1 and fl2 have reported, picker pk1 has not.
struct Yard {
  map::Site site;
  AreaLedger ledger;
  OrderBook book;
  KnownNames names;
  std::map<std::string, std::string> parked_at{{"fl1", "H1"}, {"fl2", "H2"}, {"pk1", "H3"}};
  std::set<std::string> registered{"fl1", "fl2"};
  std::set<std::string> free_robots{"fl1"};
  bool reject_when_busy = false;
  int next_load = 1;

  Yard() {
    std::vector<Place> places;
    double x = 0.0;
    for (const char* id : {"A1", "A2", "A3", "R1", "R2", "PS1", "PS2"}) {
      map::LoadingArea area;
      area.id = id;
      area.pose = {x, 0.0, 0.0};
      x += 2.0;
      if (area.id[0] == 'R') area.boxes = map::BoxStock{"BX", 5};
      site.loading_areas.push_back(area);
      places.push_back({area.id, area.pose});
      names.areas.push_back(area.id);
    }
    for (const char* id : {"H1", "H2", "H3"}) {
      site.homes.push_back({id, {x, 5.0, 0.0}});
      names.homes.push_back(id);
      x += 2.0;
    }
    site.packing = map::Packing{3, {"PS1", "PS2"}, {"A3"}, {"A2"}};
    names.robots = {"fl1", "fl2", "pk1"};
    names.fleets = {"forklifts", "pickers"};
    names.fleet_of_robot = {{"fl1", "forklifts"}, {"fl2", "forklifts"}, {"pk1", "pickers"}};
    ledger = AreaLedger(places);
    for (const char* place : {"A1", "PS1", "PS2"}) ledger.record({next_load++, "pallet", {}, place, ""});
  }

  OrderIntake intake() const {
    return OrderIntake({.book = book,
                        .ledger = ledger,
                        .names = names,
                        .site = site,
                        .parked_at = parked_at,
                        .registered = registered,
                        .free_robots = free_robots,
                        .reject_when_busy = reject_when_busy,
                        .max_pickable_mass = 5.0});
  }
  IntakeDecision decide(const model::OrderRequest& request) const { return intake().decide(request); }

  std::int64_t add(Order draft) { return book.create(std::move(draft), 0.0).id; }
  std::int64_t pick_order(const std::string& place, const std::string& station, int boxes) {
    Order draft;
    draft.kind = OrderKind::kPick;
    draft.pick_area = place;
    draft.drop_area = station;
    draft.lines = place + ",BX," + std::to_string(boxes) + "\n";
    return add(std::move(draft));
  }
};

model::OrderRequest transport(const std::string& pick, const std::string& drop) {
  model::OrderRequest request;
  request.request_id = "r1";
  request.pick_area = pick;
  request.drop_area = drop;
  return request;
}

model::OrderRequest move_to(const std::string& robot, const std::string& place) {
  model::OrderRequest request;
  request.request_id = "m1";
  request.kind = "move";
  request.robot_id = robot;
  request.drop_area = place;
  return request;
}

model::OrderRequest pick_list(const std::string& lines, const std::string& station = "PS1") {
  model::OrderRequest request;
  request.request_id = "p1";
  request.kind = "pick";
  request.drop_area = station;
  request.lines = lines;
  return request;
}

void expect_refused(const IntakeDecision& decision, const std::string& error) {
  EXPECT_FALSE(decision.reply.accepted);
  EXPECT_EQ(decision.reply.error, error);
  EXPECT_EQ(decision.reply.order_id, 0);
  EXPECT_EQ(decision.reply.order_count, 0);
  EXPECT_TRUE(decision.drafts.empty());
}

TEST(OrderIntake, AnAcceptedTransportIsOneDraftAsRequested) {
  Yard yard;
  model::OrderRequest request = transport("A1", "A2");
  request.priority = 7;
  request.fleet_id = "forklifts";
  const IntakeDecision decision = yard.decide(request);
  EXPECT_TRUE(decision.reply.accepted);
  EXPECT_EQ(decision.reply.request_id, "r1");
  EXPECT_EQ(decision.reply.error, "");
  EXPECT_EQ(decision.reply.order_count, 1);
  EXPECT_EQ(decision.reply.order_id, 0) << "the id is the book's, once the draft is added";
  ASSERT_EQ(decision.drafts.size(), 1u);
  const Order& draft = decision.drafts.front();
  EXPECT_EQ(draft.kind, OrderKind::kTransport);
  EXPECT_EQ(draft.request_id, "r1");
  EXPECT_EQ(draft.pick_area, "A1");
  EXPECT_EQ(draft.drop_area, "A2");
  EXPECT_EQ(draft.fleet_id, "forklifts");
  EXPECT_EQ(draft.priority, 7);
  EXPECT_FALSE(draft.robot_requested);
  ASSERT_EQ(draft.steps.size(), 2u);
  EXPECT_EQ(draft.steps[0].place, "A1");
  EXPECT_EQ(draft.steps[1].place, "A2");
  EXPECT_TRUE(yard.book.all().empty()) << "the intake adds nothing itself";
}

TEST(OrderIntake, AnUnknownAreaIsRefusedNamingTheField) {
  Yard yard;
  expect_refused(yard.decide(transport("A1", "Z9")),
                 "to: unknown loading area 'Z9'; valid: A1, A2, A3, R1, R2, PS1, PS2");
  expect_refused(yard.decide(transport("Z9", "A2")),
                 "from: unknown loading area 'Z9'; valid: A1, A2, A3, R1, R2, PS1, PS2");
  model::OrderRequest bad_kind = transport("A1", "A2");
  bad_kind.kind = "fly";
  const IntakeDecision decision = yard.decide(bad_kind);
  EXPECT_FALSE(decision.reply.accepted);
  EXPECT_EQ(decision.reply.error.rfind("kind: 'fly' is not an order kind", 0), 0u) << decision.reply.error;
}

TEST(OrderIntake, ATransportWhosePickAreaIsEmptyIsRefused) {
  Yard yard;
  expect_refused(yard.decide(transport("A2", "A3")), "loading area 'A2' holds no pallet to pick");
}

TEST(OrderIntake, ATransportFromAPalletPromisedToAnOpenOrderIsRefusedNamingThatOrder) {
  Yard yard;
  Order open;
  open.pick_area = "A1";
  open.drop_area = "A3";
  const std::int64_t id = yard.add(std::move(open));
  std::string expected = "the pallet on loading area 'A1' is promised to order ";
  expected += std::to_string(id);
  expected += ", which picks it up";
  expect_refused(yard.decide(transport("A1", "A2")), expected);
}

TEST(OrderIntake, AMoveToAParkingPlaceAnotherRobotParksAtIsRefused) {
  Yard yard;
  expect_refused(yard.decide(move_to("fl1", "H2")), "parking place 'H2' is fl2's");
  EXPECT_TRUE(yard.decide(move_to("fl2", "H2")).reply.accepted) << "its own parking place";
  // pk1 never reported: it stands nowhere yet, so its configured home is free to park at.
  const IntakeDecision decision = yard.decide(move_to("fl1", "H3"));
  EXPECT_TRUE(decision.reply.accepted) << decision.reply.error;
  ASSERT_EQ(decision.drafts.size(), 1u);
  EXPECT_EQ(decision.drafts.front().kind, OrderKind::kMove);
  EXPECT_EQ(decision.drafts.front().robot_id, "fl1");
  EXPECT_TRUE(decision.drafts.front().robot_requested);
}

TEST(OrderIntake, AMoveToAPlaceAnOpenMoveGoesToIsRefusedNamingThatOrder) {
  Yard yard;
  yard.parked_at.erase("pk1");
  Order open;
  open.kind = OrderKind::kMove;
  open.drop_area = "H3";
  const std::int64_t id = yard.add(std::move(open));
  std::string expected = "parking place 'H3' is promised to order ";
  expected += std::to_string(id);
  expected += ", which goes there";
  expect_refused(yard.decide(move_to("fl1", "H3")), expected);
  ASSERT_EQ(yard.book.transition(id, OrderStatus::kCancelled, 1.0, "test"), TransitionResult::kApplied);
  EXPECT_TRUE(yard.decide(move_to("fl1", "H3")).reply.accepted) << "a cancelled move promises nothing";
}

TEST(OrderIntake, AnOrderNamingARobotNeverSeenIsRefused) {
  Yard yard;
  model::OrderRequest request = transport("A1", "A2");
  request.robot_id = "pk1";
  expect_refused(yard.decide(request),
                 "robot pk1 is configured but has not been seen: no fleet-agent --id pk1 has reported to this "
                 "server (seen: fl1, fl2)");
  expect_refused(yard.decide(move_to("pk1", "H3")),
                 "robot pk1 is configured but has not been seen: no fleet-agent --id pk1 has reported to this "
                 "server (seen: fl1, fl2)");
}

TEST(OrderIntake, WhyUnseenNamesTheRobotsSeenOnlyWhenThereAreAny) {
  EXPECT_EQ(why_unseen("fl1", {"fl1"}), std::nullopt);
  EXPECT_EQ(why_unseen("fl1", {}),
            "robot fl1 is configured but has not been seen: no fleet-agent --id fl1 has reported to this server");
}

TEST(OrderIntake, RejectWhenBusyRefusesWhenNoRobotIsFree) {
  Yard yard;
  yard.free_robots.clear();
  EXPECT_TRUE(yard.decide(transport("A1", "A2")).reply.accepted) << "the setting is off: the order queues";
  yard.reject_when_busy = true;
  expect_refused(yard.decide(transport("A1", "A2")), "no robot is free (server.reject_when_busy is on)");
  yard.free_robots = {"fl2"};
  EXPECT_TRUE(yard.decide(transport("A1", "A2")).reply.accepted);
}

TEST(OrderIntake, RejectWhenBusyComesAfterTheRequestsOwnProblems) {
  Yard yard;
  yard.free_robots.clear();
  yard.reject_when_busy = true;
  expect_refused(yard.decide(transport("A2", "A3")), "loading area 'A2' holds no pallet to pick");
}

TEST(OrderIntake, APickListCutIntoToursGivesOneOrderPerTour) {
  Yard yard;
  const IntakeDecision decision = yard.decide(pick_list("R1,BX,2\nR2,BX,1\n"));
  ASSERT_TRUE(decision.reply.accepted) << decision.reply.error;
  EXPECT_EQ(decision.reply.request_id, "p1");
  EXPECT_EQ(decision.reply.order_count, 2);
  ASSERT_EQ(decision.drafts.size(), 2u);
  EXPECT_EQ(decision.drafts[0].kind, OrderKind::kPick);
  EXPECT_EQ(decision.drafts[0].pick_area, "R1");
  EXPECT_EQ(decision.drafts[0].lines, "R1,BX,2\n");
  EXPECT_EQ(decision.drafts[0].drop_area, "PS1");
  EXPECT_EQ(decision.drafts[1].pick_area, "R2");
  EXPECT_EQ(decision.drafts[1].lines, "R2,BX,1\n");
  EXPECT_EQ(decision.drafts[1].request_id, "p1");
  for (const Order& draft : decision.drafts) EXPECT_FALSE(draft.steps.empty());
}

TEST(OrderIntake, ALaterTourMovesOnToTheNextStationWhenTheEarlierOnesFillThePallet) {
  Yard yard;
  yard.pick_order("R2", "PS1", 1);  // PS1's pallet (3 boxes) has room for 2 more
  const IntakeDecision decision = yard.decide(pick_list("R1,BX,4\n"));
  ASSERT_TRUE(decision.reply.accepted) << decision.reply.error;
  ASSERT_EQ(decision.drafts.size(), 2u);
  EXPECT_EQ(decision.drafts[0].drop_area, "PS1");
  EXPECT_EQ(decision.drafts[1].drop_area, "PS2") << "the first tour's 2 boxes fill PS1";
}

TEST(OrderIntake, APickListAskingForMoreBoxesThanAreLeftIsRefused) {
  Yard yard;
  yard.pick_order("R1", "PS1", 4);
  const std::int64_t cancelled = yard.pick_order("R2", "PS2", 5);
  ASSERT_EQ(yard.book.transition(cancelled, OrderStatus::kCancelled, 1.0, "test"), TransitionResult::kApplied);
  const auto left = yard.intake().boxes_left();
  ASSERT_EQ(left.size(), 2u);
  EXPECT_EQ(left.at("R1").count, 1) << "an open pick order has its boxes";
  EXPECT_EQ(left.at("R2").count, 5) << "a cancelled one gives them back";
  const IntakeDecision decision = yard.decide(pick_list("R1,BX,2\n"));
  EXPECT_FALSE(decision.reply.accepted);
  EXPECT_EQ(decision.reply.error.rfind("lines: pick list", 0), 0u) << decision.reply.error;
  EXPECT_NE(decision.reply.error.find("holds 1 box of BX"), std::string::npos) << decision.reply.error;
  EXPECT_TRUE(decision.drafts.empty());
}

TEST(OrderIntake, AnUnreadablePickListIsRefusedNamingTheLines) {
  Yard yard;
  const IntakeDecision decision = yard.decide(pick_list("R1,BX,two\n"));
  EXPECT_FALSE(decision.reply.accepted);
  EXPECT_EQ(decision.reply.error.rfind("lines: pick list:1", 0), 0u) << decision.reply.error;
}

TEST(OrderIntake, APickListForARobotNeverSeenIsRefused) {
  Yard yard;
  model::OrderRequest request = pick_list("R1,BX,1\n");
  request.robot_id = "pk1";
  const IntakeDecision decision = yard.decide(request);
  EXPECT_FALSE(decision.reply.accepted);
  EXPECT_EQ(decision.reply.error.rfind("robot pk1 is configured but has not been seen", 0), 0u) << decision.reply.error;
}

}  // namespace
}  // namespace fleet::orders
