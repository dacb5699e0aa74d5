#include "server/reply_desk.hpp"

#include "common/clock.hpp"
#include "dds/qos.hpp"

namespace fleet::server {

namespace {
constexpr double kReplyRetentionWallS = 30.0;  // a requester has this long to read its reply
}  // namespace

ReplyDesk::ReplyDesk(dds::Participant& participant) : writer_(participant, dds::qos::latched_state()) {}

void ReplyDesk::reply(const model::RequestReply& answer) {
  writer_.write(answer);
  written_[answer.request_id] = SimClock::wall_now();
}

void ReplyDesk::forget_old() {
  // Replies are latched only long enough for their requester to read them; unregistering keeps
  // the writer's history bounded.
  const double now = SimClock::wall_now();
  for (auto it = written_.begin(); it != written_.end();) {
    if (now - it->second > kReplyRetentionWallS) {
      writer_.unregister({it->first, false, 0, ""});
      it = written_.erase(it);
    } else {
      ++it;
    }
  }
}

}  // namespace fleet::server
