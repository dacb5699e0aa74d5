#pragma once

#include <map>
#include <string>

#include "dds/topics.hpp"

namespace fleet::server {

/// The server's answers to requests and commands over DDS (RequestReply, latched so an answer
/// written before its requester's reader matched is still delivered), each kept only as long as
/// its requester needs to read it, so the writer's history stays bounded.
class ReplyDesk {
 public:
  explicit ReplyDesk(dds::Participant& participant);

  void reply(const model::RequestReply& answer);
  /// Unregisters the answers their requesters have had time to read (call every loop).
  void forget_old();

 private:
  dds::Writer<model::RequestReply> writer_;
  std::map<std::string, double> written_;  ///< request id -> wall time
};

}  // namespace fleet::server
