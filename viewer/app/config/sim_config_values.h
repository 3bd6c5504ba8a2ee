// The values of the `sim:` section that are more than a number: event windows relative to the sequence
// start, events ({window, value}) and extrinsics ({translation_m, rotation_rpy_deg} or {matrix}), read and
// written exactly (see sim_config.h for the conventions). Internal to uf_app_config (yaml-cpp).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "odometry/sim/time_window.h"
#include "odometry/types/se3.h"
#include "viewer/app/config/schema.h"

namespace uf::app::config {

// [begin_s, end_s] relative to `start` -> absolute stamps; end <= begin is an error.
Status ReadWindow(const KeyPath& at, const YAML::Node& node, Stamp start, sim::TimeWindow& window);
// "[begin_s, end_s]" relative to `start`, exact decimal seconds.
std::string FormatWindow(const sim::TimeWindow& window, Stamp start);

// [[b, e], ...]: the list given replaces `windows`.
Status ReadWindows(const KeyPath& at, const YAML::Node& node, Stamp start,
                   std::vector<sim::TimeWindow>& windows);
std::string FormatWindows(const std::vector<sim::TimeWindow>& windows, Stamp start);

// [{window: [b, e], KEY: value}, ...], both keys required, the value read and written by `codec`.
template <typename T>
Status ReadEvents(const KeyPath& at, const YAML::Node& node, Stamp start, const std::string& key,
                  const Codec<T>& codec, std::vector<std::pair<sim::TimeWindow, T>>& events) {
  if (!node.IsSequence()) return at.Error(node, "expected a list, got '" + Text(node) + "'");
  using Event = std::pair<sim::TimeWindow, T>;
  std::vector<Event> read(node.size());
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node& item = node[i];
    if (!item.IsMap() || !item["window"] || !item[key])
      return at[i].Error(item,
                         "expected {window: [begin_s, end_s], " + key + ": ...}, got '" + Text(item) + "'");
    Schema<Event> event;
    event.Custom(
        "window",
        [start](const KeyPath& w, const YAML::Node& n, Event& e) { return ReadWindow(w, n, start, e.first); },
        nullptr, "", "");
    event.Key(key, &Event::second, codec, "", "");
    if (Status s = ReadMap(event, at[i], item, read[i]); !s.ok()) return s;
  }
  events = std::move(read);
  return {};
}

template <typename T>
std::string FormatEvents(const std::vector<std::pair<sim::TimeWindow, T>>& events, Stamp start,
                         const std::string& key, const Codec<T>& codec) {
  std::string list;
  for (const auto& [window, value] : events)
    list += (list.empty() ? "{window: " : ", {window: ") + FormatWindow(window, start) + ", " + key + ": " +
            codec.write(value).text + "}";
  return "[" + list + "]";
}

// T_body_sensor: read from {translation_m, rotation_rpy_deg} (each part optional: the other keeps the
// current value) or {matrix: [16 numbers]}; written as the exact matrix, with its translation and
// roll-pitch-yaw in a comment.
Codec<SE3> ExtrinsicCodec();

}  // namespace uf::app::config
