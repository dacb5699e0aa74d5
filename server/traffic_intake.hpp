#pragma once

#include <functional>

#include "dds/topics.hpp"
#include "model/traffic_requests.hpp"
#include "server/sender_gate.hpp"

namespace fleet::server {

/// The server's reading of what robots ask of traffic control, from both topics it comes on: each
/// TrafficRequest (the route, when it changes) and each TrafficProgress (between them) becomes one
/// whole request (model::TrafficRequestJoin), taken only from writers the gate admits.
class TrafficIntake {
 public:
  TrafficIntake(dds::Participant& participant, SenderGate& gate);

  /// Calls `fn` with each whole request received since the last call, in the order taken.
  void take(const std::function<void(model::TrafficRequest&&, const dds::SampleInfo&)>& fn);

 private:
  SenderGate& gate_;
  dds::Reader<model::TrafficRequest> request_reader_;
  dds::Reader<model::TrafficProgress> progress_reader_;
  model::TrafficRequestJoin join_;
};

}  // namespace fleet::server
