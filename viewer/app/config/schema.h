// The schema of a configuration section: each key declared once, as {key path, field, unit, meaning}, with
// its type deduced from the field and read and written by the codec of that type (yaml_values.h) or by one
// given. Generic code driven by the declaration reads a section (unknown keys are errors listing the known
// ones; type errors name the file, key, line and value), writes it (the text `run` saves as config.yaml,
// which reads back to the same values) and lists its documented defaults (docs/CONFIG.md). Value ranges
// stay in the option structs' Validate(). Internal to uf_app_config (yaml-cpp).
//
//   Schema<VoxelMapConfig> map;
//   map.Key("voxel_m", &VoxelMapConfig::voxel_m, "m", "voxel edge of the local map");
//   Schema<LidarOdometryConfig> lo("lo");
//   lo.Nest("map", &LidarOdometryConfig::map, map);   // lo.map.voxel_m
#pragma once

#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "viewer/app/config/yaml_values.h"

namespace uf::app::config {

// A value as the file holds it.
struct ValueText {
  ValueText() = default;
  ValueText(std::string value) : text(std::move(value)) {}  // NOLINT: a value is its text

  std::string text;                // on the key's line: "0.5", "[0, 0, 0]", "{matrix: [...]}"
  std::vector<std::string> lines;  // instead, lines under the key, one level deeper ("- {topic: ...}")
  std::string comment;             // after the value, as "  # comment"
  std::string doc;                 // the documented default, where it reads better than `text`
  bool omitted = false;            // not written (an optional list left empty); `text` documents it
};

// How a value of type T is read from a node and written.
template <typename T>
struct Codec {
  std::function<Status(const KeyPath&, const YAML::Node&, T&)> read;
  std::function<ValueText(const T&)> write;
};

// The codec of T's Read and Format overloads (yaml_values.h).
template <typename T>
Codec<T> PlainCodec() {
  return {[](const KeyPath& at, const YAML::Node& node, T& value) { return Read(at, node, value); },
          [](const T& value) { return ValueText{Format(value)}; }};
}

// A value written as its name: `parse` gives the value of a name or the error text, `name` the name.
template <typename T>
Codec<T> NamedCodec(std::function<Expected<T>(const std::string&)> parse,
                    std::function<std::string(T)> name) {
  return {[parse](const KeyPath& at, const YAML::Node& node, T& value) -> Status {
            Expected<T> parsed = parse(Text(node));
            if (!parsed) return at.Error(node, parsed.error());
            value = *parsed;
            return {};
          },
          [name](const T& value) { return ValueText{name(value)}; }};
}

template <typename Root>
class Schema {
 public:
  struct Entry {
    std::string path;  // dotted below the section: "map.voxel_m"
    std::string unit, doc;
    std::function<Status(const KeyPath&, const YAML::Node&, Root&)> read;
    std::function<ValueText(const Root&)> write;
  };

  // `section`: the top-level key ("lo"); empty for a part nested into another schema.
  explicit Schema(std::string section = "") : section_(std::move(section)) {}

  // The field `access` gives: a member pointer, or a generic lambda returning a reference to the field
  // ([](auto& c) -> auto& { return c.model.rate_hz; }). Read and written by its type's codec, or `codec`.
  template <typename Access>
  Schema& Key(std::string path, Access access, std::string unit, std::string doc) {
    return Key(std::move(path), access, PlainCodec<FieldOf<Access>>(), std::move(unit), std::move(doc));
  }
  template <typename Access, typename Field>
  Schema& Key(std::string path, Access access, Codec<Field> codec, std::string unit, std::string doc) {
    static_assert(std::is_same_v<Field, FieldOf<Access>>, "the codec's type is not the field's");
    entries_.push_back(
        {std::move(path), std::move(unit), std::move(doc),
         [access, read = codec.read](const KeyPath& at, const YAML::Node& node, Root& root) {
           return read(at, node, std::invoke(access, root));
         },
         [access, write = codec.write](const Root& root) { return write(std::invoke(access, root)); }});
    return *this;
  }

  // A key whose value needs more than one field (a [width, height] pair, windows relative to the start).
  Schema& Custom(std::string path, std::function<Status(const KeyPath&, const YAML::Node&, Root&)> read,
                 std::function<ValueText(const Root&)> write, std::string unit, std::string doc) {
    entries_.push_back({std::move(path), std::move(unit), std::move(doc), std::move(read), std::move(write)});
    return *this;
  }

  // Every key of `sub` under `prefix` ("": at this level), on the part of Root that `access` gives.
  template <typename Access, typename Sub>
  Schema& Nest(const std::string& prefix, Access access, const Schema<Sub>& sub) {
    static_assert(std::is_same_v<Sub, FieldOf<Access>>, "the nested schema is not of the accessed part");
    const auto under = [&prefix](const std::string& path) {
      return prefix.empty() ? path : prefix + "." + path;
    };
    for (const typename Schema<Sub>::Entry& e : sub.entries()) {
      entries_.push_back(
          {under(e.path), e.unit, e.doc,
           [access, read = e.read](const KeyPath& at, const YAML::Node& node, Root& root) {
             return read(at, node, std::invoke(access, root));
           },
           [access, write = e.write](const Root& root) { return write(std::invoke(access, root)); }});
    }
    for (const std::string& group : sub.flow_groups()) flow_groups_.push_back(under(group));
    return *this;
  }

  // The map at `group` ("origin", "gnss.noise.single") is written on one line: "origin: {a: 1, b: 2}".
  Schema& Flow(std::string group) {
    flow_groups_.push_back(std::move(group));
    return *this;
  }

  // A top-level key read before the others wherever it stands (sim's start_time_s: windows are relative
  // to it).
  Schema& ReadFirst(std::string key) {
    read_first_.push_back(std::move(key));
    return *this;
  }

  const std::string& section() const { return section_; }
  const std::vector<Entry>& entries() const { return entries_; }
  const std::vector<std::string>& flow_groups() const { return flow_groups_; }
  const std::vector<std::string>& read_first() const { return read_first_; }

 private:
  template <typename Access>
  using FieldOf = std::remove_cvref_t<std::invoke_result_t<Access, Root&>>;

  std::string section_;
  std::vector<Entry> entries_;
  std::vector<std::string> flow_groups_, read_first_;
};

// The schema `make` builds, built once (the sections' schema accessors).
template <auto make>
const auto& BuiltOnce() {
  static const auto schema = make();
  return schema;
}

// The keys of a schema as a tree of maps, in declaration order: groups (maps of settings) and leaves.
struct KeyNode {
  std::string key;
  int entry = -1;  // a leaf's index in the schema's entries; -1 for a group
  bool flow = false;
  std::vector<KeyNode> children;
};
KeyNode BuildKeyTree(const std::vector<std::string>& paths, const std::vector<std::string>& flow_groups);

// Reads the map `node` (null: nothing to read) with the keys of `group`, `first` before the others; each
// leaf through `read`. Unknown keys are errors listing the known ones.
using ReadLeaf = std::function<Status(int entry, const KeyPath& at, const YAML::Node& value)>;
Status ReadKeys(const KeyPath& at, const YAML::Node& node, const KeyNode& group,
                const std::vector<std::string>& first, const ReadLeaf& read);

// "SECTION:\n  key: value\n  group:\n    key: value\n...", each leaf's text from `write`.
using WriteLeaf = std::function<ValueText(int entry)>;
std::string EmitKeys(const std::string& section, const KeyNode& tree, const WriteLeaf& write);
// "{key: value, group: {key: value}}".
std::string FlowMap(const KeyNode& tree, const WriteLeaf& write);

// One row of a section's documented defaults.
struct DocRow {
  std::string key, default_value, unit, meaning;
};
// "| key | default | unit | meaning |" and a row per key.
std::string MarkdownTable(const std::vector<DocRow>& rows);

template <typename Root>
KeyNode KeyTreeOf(const Schema<Root>& schema) {
  std::vector<std::string> paths;
  for (const auto& entry : schema.entries()) paths.push_back(entry.path);
  return BuildKeyTree(paths, schema.flow_groups());
}

// Reads the map `node` at `at` onto `root` (keys not given keep their value).
template <typename Root>
Status ReadMap(const Schema<Root>& schema, const KeyPath& at, const YAML::Node& node, Root& root) {
  return ReadKeys(at, node, KeyTreeOf(schema), schema.read_first(),
                  [&](int entry, const KeyPath& key, const YAML::Node& value) {
                    return schema.entries()[entry].read(key, value, root);
                  });
}

// Reads the section's map `node` of `file` onto `root`.
template <typename Root>
Status ReadSection(const Schema<Root>& schema, const std::string& file, const YAML::Node& node, Root& root) {
  return ReadMap(schema, KeyPath(file, schema.section()), node, root);
}

// The section with every key of `root`, readable by ReadSection.
template <typename Root>
std::string EmitSection(const Schema<Root>& schema, const Root& root) {
  return EmitKeys(schema.section(), KeyTreeOf(schema),
                  [&](int entry) { return schema.entries()[entry].write(root); });
}

// "{key: value, ...}" on one line (list items such as {topic: /imu, kind: imu}).
template <typename Root>
std::string EmitFlow(const Schema<Root>& schema, const Root& root) {
  return FlowMap(KeyTreeOf(schema), [&](int entry) { return schema.entries()[entry].write(root); });
}

// The section's keys with the values of `defaults`.
template <typename Root>
std::vector<DocRow> DocRows(const Schema<Root>& schema, const Root& defaults) {
  std::vector<DocRow> rows;
  for (const auto& entry : schema.entries()) {
    const ValueText value = entry.write(defaults);
    rows.push_back({schema.section() + "." + entry.path, value.doc.empty() ? value.text : value.doc,
                    entry.unit, entry.doc});
  }
  return rows;
}

}  // namespace uf::app::config
