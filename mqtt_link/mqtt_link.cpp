#include "mqtt_link/mqtt_link.hpp"

#include <mqtt/async_client.h>

#include <chrono>

namespace fleet::mqtt_link {

namespace {
/// Messages kept for the loop at most: a loop that stalls loses the oldest, never memory.
constexpr std::size_t kInboxLimit = 100000;

/// Runs a function when the broker acknowledges one publication, then deletes itself.
class AcknowledgementListener : public mqtt::iaction_listener {
 public:
  explicit AcknowledgementListener(std::function<void()> acknowledged) : acknowledged_(std::move(acknowledged)) {}
  void on_success(const mqtt::token&) override {
    acknowledged_();
    delete this;
  }
  void on_failure(const mqtt::token&) override { delete this; }

 private:
  std::function<void()> acknowledged_;
};

}  // namespace

MqttLink::MqttLink(const std::string& broker, const std::string& client_id, std::vector<std::string> subscriptions,
                   std::optional<LastWill> will)
    : client_(std::make_unique<mqtt::async_client>(broker, client_id, mqtt::create_options(MQTTVERSION_3_1_1))),
      subscriptions_(std::move(subscriptions)) {
  client_->set_connected_handler([this](const std::string&) { on_connected(); });
  client_->set_message_callback([this](mqtt::const_message_ptr message) {
    std::lock_guard lock(mutex_);
    if (inbox_.size() >= kInboxLimit) inbox_.pop_front();
    inbox_.push_back({message->get_topic(), message->to_string()});
  });
  auto builder = mqtt::connect_options_builder();
  if (will) builder.will(mqtt::message(will->topic, will->payload, 1, true));
  auto options = builder.clean_session(true)
                     .keep_alive_interval(std::chrono::seconds(5))
                     .connect_timeout(std::chrono::seconds(5))
                     .automatic_reconnect(std::chrono::seconds(1), std::chrono::seconds(30))
                     .finalize();
  client_->connect(options);
}

MqttLink::~MqttLink() {
  try {
    if (client_->is_connected()) client_->disconnect()->wait_for(std::chrono::seconds(2));
  } catch (const mqtt::exception&) {
    // Leaving anyway: the broker drops the session when the socket closes.
  }
}

void MqttLink::on_connected() {
  {
    std::lock_guard lock(mutex_);
    ++connections_;
  }
  for (const std::string& topic : subscriptions_) client_->subscribe(topic, 1);
}

bool MqttLink::connected() const {
  return client_->is_connected();
}

int MqttLink::connections() const {
  std::lock_guard lock(mutex_);
  return connections_;
}

bool MqttLink::publish(const std::string& topic, const std::string& payload, int qos, bool retained) {
  if (!client_->is_connected()) return false;
  try {
    client_->publish(topic, payload.data(), payload.size(), qos, retained);
    return true;
  } catch (const mqtt::exception&) {
    return false;  // lost the connection meanwhile; reconnecting
  }
}

bool MqttLink::publish_acknowledged(const std::string& topic, const std::string& payload,
                                    std::function<void()> acknowledged) {
  if (!client_->is_connected()) return false;
  auto* listener = new AcknowledgementListener(std::move(acknowledged));
  try {
    client_->publish(topic, payload.data(), payload.size(), 1, false, nullptr, *listener);
    return true;
  } catch (const mqtt::exception&) {
    delete listener;  // never handed to the client
    return false;
  }
}

std::vector<MqttMessage> MqttLink::take() {
  std::lock_guard lock(mutex_);
  std::vector<MqttMessage> out(std::make_move_iterator(inbox_.begin()), std::make_move_iterator(inbox_.end()));
  inbox_.clear();
  return out;
}

}  // namespace fleet::mqtt_link
