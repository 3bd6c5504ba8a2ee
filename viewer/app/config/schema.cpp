#include "viewer/app/config/schema.h"

#include <algorithm>

namespace uf::app::config {
namespace {

KeyNode* Child(KeyNode& group, const std::string& key) {
  for (KeyNode& child : group.children)
    if (child.key == key) return &child;
  return nullptr;
}

const KeyNode* Child(const KeyNode& group, const std::string& key) {
  for (const KeyNode& child : group.children)
    if (child.key == key) return &child;
  return nullptr;
}

std::string KnownKeys(const KeyNode& group) {
  std::string known;
  for (const KeyNode& child : group.children) known += (known.empty() ? "" : ", ") + child.key;
  return known;
}

Status ReadKey(const KeyPath& at, const YAML::Node& key, const YAML::Node& value, const KeyNode& group,
               const ReadLeaf& read) {
  const std::string name = Text(key);
  const KeyNode* child = Child(group, name);
  if (child == nullptr || !key.IsScalar())
    return (at / name).Error(key, "unknown key (expected " + KnownKeys(group) + ")");
  if (child->entry >= 0) return read(child->entry, at / name, value);
  return ReadKeys(at / name, value, *child, {}, read);
}

}  // namespace

std::string FlowMap(const KeyNode& group, const WriteLeaf& write) {
  std::string text;
  for (const KeyNode& child : group.children) {
    std::string value;
    if (child.entry >= 0) {
      const ValueText leaf = write(child.entry);
      if (leaf.omitted) continue;
      value = leaf.text;
    } else {
      value = FlowMap(child, write);
    }
    text += (text.empty() ? "" : ", ") + child.key + ": " + value;
  }
  return "{" + text + "}";
}

namespace {

void EmitBlock(const KeyNode& group, int indent, const WriteLeaf& write, std::string& out) {
  const std::string pad(2 * indent, ' ');
  for (const KeyNode& child : group.children) {
    if (child.entry < 0) {
      if (child.flow) {
        out += pad + child.key + ": " + FlowMap(child, write) + "\n";
      } else {
        out += pad + child.key + ":\n";
        EmitBlock(child, indent + 1, write, out);
      }
      continue;
    }
    const ValueText value = write(child.entry);
    if (value.omitted) continue;
    if (!value.lines.empty()) {
      out += pad + child.key + ":\n";
      for (const std::string& line : value.lines) out += pad + "  " + line + "\n";
      continue;
    }
    out += pad + child.key + ":" + (value.text.empty() ? "" : " " + value.text) +
           (value.comment.empty() ? "" : "  # " + value.comment) + "\n";
  }
}

// A Markdown table cell: '|' would end it.
std::string Cell(const std::string& text) {
  std::string cell;
  for (char c : text) cell += c == '|' ? std::string("\\|") : std::string(1, c);
  return cell;
}

}  // namespace

KeyNode BuildKeyTree(const std::vector<std::string>& paths, const std::vector<std::string>& flow_groups) {
  KeyNode root;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    KeyNode* group = &root;
    std::string prefix;
    for (std::size_t begin = 0;;) {
      const std::size_t dot = paths[i].find('.', begin);
      const std::string key =
          paths[i].substr(begin, dot == std::string::npos ? std::string::npos : dot - begin);
      prefix += (prefix.empty() ? "" : ".") + key;
      KeyNode* child = Child(*group, key);
      if (child == nullptr) {
        child = &group->children.emplace_back();
        child->key = key;
        child->flow = std::find(flow_groups.begin(), flow_groups.end(), prefix) != flow_groups.end();
      }
      if (dot == std::string::npos) {
        child->entry = static_cast<int>(i);
        break;
      }
      group = child;
      begin = dot + 1;
    }
  }
  return root;
}

Status ReadKeys(const KeyPath& at, const YAML::Node& node, const KeyNode& group,
                const std::vector<std::string>& first, const ReadLeaf& read) {
  if (node.IsNull()) return {};
  if (!node.IsMap()) return at.Error(node, "expected a map of settings, got '" + Text(node) + "'");
  // YAML leaves a key given twice to the reader; one of the two would win silently.
  std::vector<std::string> seen;
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) continue;
    if (std::find(seen.begin(), seen.end(), kv.first.Scalar()) != seen.end())
      return (at / kv.first.Scalar()).Error(kv.first, "given twice in the same section");
    seen.push_back(kv.first.Scalar());
  }
  for (const std::string& key : first) {
    for (const auto& kv : node)
      if (kv.first.IsScalar() && kv.first.Scalar() == key)
        if (Status s = ReadKey(at, kv.first, kv.second, group, read); !s.ok()) return s;
  }
  for (const auto& kv : node) {
    if (kv.first.IsScalar() && std::find(first.begin(), first.end(), kv.first.Scalar()) != first.end())
      continue;
    if (Status s = ReadKey(at, kv.first, kv.second, group, read); !s.ok()) return s;
  }
  return {};
}

std::string EmitKeys(const std::string& section, const KeyNode& tree, const WriteLeaf& write) {
  std::string out = section + ":\n";
  EmitBlock(tree, 1, write, out);
  return out;
}

std::string MarkdownTable(const std::vector<DocRow>& rows) {
  std::string table = "| key | default | unit | meaning |\n|---|---|---|---|\n";
  for (const DocRow& row : rows) {
    table += "| `" + Cell(row.key) + "` | `" + Cell(row.default_value) + "` | " +
             Cell(row.unit.empty() ? "-" : row.unit) + " | " + Cell(row.meaning) + " |\n";
  }
  return table;
}

}  // namespace uf::app::config
