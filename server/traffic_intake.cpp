#include "server/traffic_intake.hpp"

namespace fleet::server {

TrafficIntake::TrafficIntake(dds::Participant& participant, SenderGate& gate)
    : gate_(gate),
      request_reader_(participant, dds::qos::live_state(), dds::robot_report_partitions()),
      progress_reader_(participant, dds::qos::live_state(), dds::robot_report_partitions()) {}

void TrafficIntake::take(const std::function<void(model::TrafficRequest&&, const dds::SampleInfo&)>& fn) {
  // Requests first: a route and the progress along it taken in one call apply in that order.
  request_reader_.take([&](model::TrafficRequest&& request, const dds::SampleInfo& info) {
    if (!info.valid_data || !gate_.admit(request_reader_.handle(), info, request.robot_id, "fleet/TrafficRequest")) {
      return;
    }
    fn(join_.route(std::move(request)), info);
  });
  progress_reader_.take([&](model::TrafficProgress&& progress, const dds::SampleInfo& info) {
    if (!info.valid_data || !gate_.admit(progress_reader_.handle(), info, progress.robot_id, "fleet/TrafficProgress")) {
      return;
    }
    if (auto request = join_.progress(progress)) fn(std::move(*request), info);
  });
}

}  // namespace fleet::server
