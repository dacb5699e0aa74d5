#include "cli/order_injection.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "common/args.hpp"

using namespace fleet::cli;
using fleet::model::OrderInfo;
using fleet::model::PalletTruth;

namespace {
const std::vector<std::string> kAreas{"A1", "A2", "A3", "A4"};

/// A1 and A3 hold a pallet, A2 and A4 are free.
std::map<int, PalletTruth> two_pallets() {
  std::map<int, PalletTruth> pallets;
  pallets[1] = {1, {}, "A1", ""};
  pallets[2] = {2, {}, "A3", ""};
  return pallets;
}

OrderInfo order(std::int64_t id, const std::string& pick, const std::string& drop, const std::string& state) {
  OrderInfo o;
  o.order_id = id;
  o.pick_area = pick;
  o.drop_area = drop;
  o.state = state;
  return o;
}

OrdersFile parse(const std::string& text) {
  std::istringstream in(text);
  return parse_orders_csv(in);
}
}  // namespace

TEST(AreaBalance, CountsStandingPalletsAndOpenOrdersLikeTheServer) {
  auto pallets = two_pallets();
  pallets[3] = {3, {}, "", "fl1"};  // carried: stands nowhere
  std::map<std::int64_t, OrderInfo> orders{{1, order(1, "A1", "A2", "ACTIVE")}, {2, order(2, "A3", "A4", "DONE")}};
  const AreaBalance balance = area_balance(kAreas, pallets, orders);
  EXPECT_EQ(balance.at("A1"), 0);  // its pallet is promised to order 1
  EXPECT_EQ(balance.at("A2"), 1);  // order 1 brings one
  EXPECT_EQ(balance.at("A3"), 1);  // order 2 ended: it no longer counts
  EXPECT_EQ(balance.at("A4"), 0);
  EXPECT_FALSE(refusal_reason(balance, "A2", "A4"));  // chained behind order 1: the server queues it
  EXPECT_NE(refusal_reason(balance, "A1", "A4")->find("holds no pallet"), std::string::npos);
  EXPECT_NE(refusal_reason(balance, "A3", "A2")->find("occupied"), std::string::npos);
}

TEST(DrawOrder, IsValidAndTheSameForTheSameSeed) {
  const AreaBalance start = area_balance(kAreas, two_pallets(), {});
  const auto draw_five = [&](std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    AreaBalance balance = start;
    std::vector<std::string> drawn;
    for (int i = 0; i < 5; ++i) {
      const auto o = draw_order(balance, rng);
      EXPECT_TRUE(o.has_value());
      if (!o) break;
      EXPECT_FALSE(refusal_reason(balance, o->pick_area, o->drop_area)) << o->pick_area << " -> " << o->drop_area;
      book_order(balance, o->pick_area, o->drop_area);
      drawn.push_back(o->pick_area + ">" + o->drop_area);
    }
    return drawn;
  };
  EXPECT_EQ(draw_five(7), draw_five(7));
  EXPECT_NE(draw_five(7), draw_five(8));
}

TEST(DrawOrder, NothingWhenNoPalletCanBePicked) {
  std::mt19937_64 rng(1);
  EXPECT_FALSE(draw_order(area_balance(kAreas, {}, {}), rng));
  const auto any = draw_any_order(kAreas, rng);
  ASSERT_TRUE(any);
  EXPECT_NE(any->pick_area, any->drop_area);
}

TEST(ParseRate, AcceptsPerMinuteSecondAndHour) {
  EXPECT_DOUBLE_EQ(parse_rate("60/min"), 1.0);
  EXPECT_DOUBLE_EQ(parse_rate("2/s"), 2.0);
  EXPECT_DOUBLE_EQ(parse_rate("3600/h"), 1.0);
  EXPECT_DOUBLE_EQ(parse_rate("1.5/min"), 0.025);
  EXPECT_THROW(parse_rate("60"), fleet::ArgError);
  EXPECT_THROW(parse_rate("0/min"), fleet::ArgError);
  EXPECT_THROW(parse_rate("x/min"), fleet::ArgError);
}

TEST(OrdersCsv, ReadsRowsSkippingHeaderCommentsAndBlankLines) {
  const auto file =
      parse("# orders for the morning\nfrom,to,priority,delay_s\n\nA1, A2, 5, 0\r\n  # later\nA3,A4,0,1.5\n");
  ASSERT_TRUE(file.problems.empty()) << file.problems[0].message;
  ASSERT_EQ(file.rows.size(), 2u);
  EXPECT_EQ(file.rows[0].line, 4);
  EXPECT_EQ(file.rows[0].pick_area, "A1");
  EXPECT_EQ(file.rows[0].drop_area, "A2");
  EXPECT_EQ(file.rows[0].priority, 5);
  EXPECT_EQ(file.rows[1].line, 6);
  EXPECT_DOUBLE_EQ(file.rows[1].delay_s, 1.5);
}

// Regression: a file saved by a spreadsheet starts with a UTF-8 byte order mark, which made the
// header an unknown row.
TEST(OrdersCsv, AByteOrderMarkBeforeTheHeaderIsSkipped) {
  const auto file = parse(
      "\xEF\xBB\xBF"
      "from,to,priority,delay_s\nA1,A2,0,0\n");
  ASSERT_TRUE(file.problems.empty()) << file.problems[0].message;
  ASSERT_EQ(file.rows.size(), 1u);
  EXPECT_EQ(file.rows[0].pick_area, "A1");
}

TEST(OrdersCsv, FindsEveryBadRowWithItsLine) {
  const auto file = parse("A1,A2,0,0\nA1,A2,0\nA1,A2,high,0\nA1,A2,0,-1\nA3,A3,0,0\nA1,A2,0,soon\nA1,A2,5000,0\n");
  ASSERT_EQ(file.problems.size(), 6u);
  EXPECT_EQ(file.problems[0].line, 2);
  EXPECT_NE(file.problems[0].message.find("expected 4 columns"), std::string::npos);
  EXPECT_EQ(file.problems[1].line, 3);
  EXPECT_NE(file.problems[1].message.find("'high' is not an integer"), std::string::npos);
  EXPECT_EQ(file.problems[2].line, 4);
  EXPECT_NE(file.problems[2].message.find("negative"), std::string::npos);
  EXPECT_EQ(file.problems[3].line, 5);
  EXPECT_NE(file.problems[3].message.find("same area"), std::string::npos);
  EXPECT_EQ(file.problems[4].line, 6);
  EXPECT_EQ(file.problems[5].line, 7);
  EXPECT_EQ(file.rows.size(), 1u);
}

TEST(OrdersCsv, CheckNamesUnknownAreasAndRowsTheServerWouldRefuse) {
  const auto file = parse("A1,A2,0,0\nA1,B7,0,0\nA1,A4,0,0\nA2,A4,0,0\n");
  ASSERT_TRUE(file.problems.empty());
  const auto problems = check_orders_against_site(file.rows, kAreas, area_balance(kAreas, two_pallets(), {}));
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].line, 2);
  EXPECT_NE(problems[0].message.find("unknown loading area 'B7'; valid: A1, A2, A3, A4"), std::string::npos);
  EXPECT_EQ(problems[1].line, 3);  // A1's pallet goes to A2 in line 1
  EXPECT_NE(problems[1].message.find("'A1' holds no pallet"), std::string::npos);
  // Line 4 picks the pallet line 1 brings to A2: valid.
  EXPECT_TRUE(check_orders_against_site(file.rows, kAreas, std::nullopt).size() == 1u);
}
