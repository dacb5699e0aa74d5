#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace mqtt {
class async_client;
}

namespace fleet::mqtt_link {

struct MqttMessage {
  std::string topic;
  std::string payload;
};

/// A message the broker publishes for the client when its connection breaks without a
/// disconnect (MQTT's last will), retained at QoS 1.
struct LastWill {
  std::string topic;
  std::string payload;
};

/// A connection to an MQTT broker (Eclipse Paho C++): reconnects on its own with backoff (1 s
/// doubling to 30 s), subscribes again after every reconnect, and queues what arrives for the
/// caller's loop. Publishing while disconnected drops the message (VDA 5050 state is re-sent).
class MqttLink {
 public:
  /// `broker`: tcp://HOST:PORT. Connects in the background; connected() tells.
  MqttLink(const std::string& broker, const std::string& client_id, std::vector<std::string> subscriptions,
           std::optional<LastWill> will = std::nullopt);
  ~MqttLink();
  MqttLink(const MqttLink&) = delete;
  MqttLink& operator=(const MqttLink&) = delete;

  bool connected() const;
  /// Connections made, the first included: a count that grows tells of a reconnect.
  int connections() const;
  /// False when not connected (the message is dropped).
  bool publish(const std::string& topic, const std::string& payload, int qos, bool retained = false);
  /// The same at QoS 1; `acknowledged` runs on the client's thread when the broker has the
  /// message (its PUBACK).
  bool publish_acknowledged(const std::string& topic, const std::string& payload, std::function<void()> acknowledged);
  std::vector<MqttMessage> take();

 private:
  void on_connected();
  std::unique_ptr<mqtt::async_client> client_;
  std::vector<std::string> subscriptions_;
  mutable std::mutex mutex_;
  std::deque<MqttMessage> inbox_;
  int connections_ = 0;
};

}  // namespace fleet::mqtt_link
