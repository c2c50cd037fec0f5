// `orogen migrate FILE...`: rewrites graph files at the current format version in place.
//
// The file's JSON is migrated as the loader would (graph/graph_migrations.h), nothing else changes: parameters
// left at their defaults stay absent, and unknown content is kept for `orogen validate` to report. When the
// migrations only renamed members and changed values, those are patched into the original text, so the file
// keeps its layout and the diff shows the renames only. Otherwise the file is laid out anew: objects one
// member per line, arrays of numbers and strings on one line, arrays of objects (table rows) one object per
// line, except the node list, whose nodes are laid out in full.
#include <cctype>
#include <fstream>
#include <optional>
#include <string_view>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "graph/atomic_file.h"
#include "graph/graph_file.h"

namespace orogen::cli {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

std::string scalar_text(const ordered_json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

// The migrated document with the members of each object in the original file's order: a renamed member takes
// the place of the one it replaces, new members come last.
ordered_json in_original_order(const ordered_json& original, const json& migrated) {
  if (migrated.is_object() && original.is_object()) {
    std::vector<std::string> added;
    for (const auto& [k, v] : migrated.items())
      if (!original.contains(k)) added.push_back(k);
    ordered_json out = ordered_json::object();
    std::size_t next_added = 0;
    for (const auto& [k, v] : original.items()) {
      if (migrated.contains(k))
        out[k] = in_original_order(v, migrated[k]);
      else if (next_added < added.size()) {
        const auto& name = added[next_added++];
        out[name] = in_original_order(ordered_json(), migrated[name]);
      }
    }
    for (; next_added < added.size(); ++next_added)
      out[added[next_added]] = in_original_order(ordered_json(), migrated[added[next_added]]);
    return out;
  }
  if (migrated.is_array()) {
    ordered_json out = ordered_json::array();
    for (std::size_t i = 0; i < migrated.size(); ++i)
      out.push_back(
          in_original_order(original.is_array() && i < original.size() ? original[i] : ordered_json(), migrated[i]));
    return out;
  }
  // Unchanged numbers keep their text (2.0 stays 2.0).
  if (original.is_primitive() && json(original) == migrated) return original;
  return ordered_json(migrated);
}

// One line: {"a": 1, "b": [2, 3]}.
std::string inline_text(const ordered_json& j) {
  if (j.is_object()) {
    if (j.empty()) return "{}";
    std::string s = "{";
    bool first = true;
    for (const auto& [k, v] : j.items()) {
      s += (first ? "" : ", ") + json(k).dump() + ": " + inline_text(v);
      first = false;
    }
    return s + "}";
  }
  if (j.is_array()) {
    std::string s = "[";
    for (std::size_t i = 0; i < j.size(); ++i) s += (i ? ", " : "") + inline_text(j[i]);
    return s + "]";
  }
  return scalar_text(j);
}

bool all_scalars(const ordered_json& a) {
  for (const auto& e : a)
    if (e.is_structured()) return false;
  return true;
}

void write(std::string& out, const ordered_json& j, int level, const std::string& key) {
  const std::string pad(static_cast<std::size_t>(2 * level), ' ');
  const std::string inner(static_cast<std::size_t>(2 * level + 2), ' ');
  if (j.is_object()) {
    if (j.empty()) {
      out += "{}";
      return;
    }
    out += "{\n";
    bool first = true;
    for (const auto& [k, v] : j.items()) {
      if (!first) out += ",\n";
      out += inner + json(k).dump() + ": ";
      write(out, v, level + 1, k);
      first = false;
    }
    out += "\n" + pad + "}";
    return;
  }
  if (j.is_array()) {
    if (j.empty() || all_scalars(j)) {
      out += inline_text(j);
      return;
    }
    out += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      out += inner;
      const ordered_json& e = j[i];
      // Table rows and curve or gradient points: one line each. Nodes: in full.
      if (key != "nodes" && (e.is_object() || (e.is_array() && all_scalars(e)) || !e.is_structured()))
        out += inline_text(e);
      else
        write(out, e, level + 1, "");
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += pad + "]";
    return;
  }
  out += scalar_text(j);
}

// Where each key and value of a JSON text lies, to patch a file in place when a migration only renamed
// members and changed scalar values: the rest of the file keeps its layout byte for byte.
struct Span {
  std::size_t begin = 0, end = 0;
  std::vector<std::pair<Span, Span>> members;  // objects: (key, value), in file order
  std::vector<Span> elements;                  // arrays
};

class Scanner {
 public:
  explicit Scanner(const std::string& text) : s_(text) {}
  Span value() {
    skip();
    Span v;
    v.begin = i_;
    if (s_[i_] == '{') {
      ++i_;
      for (skip(); s_[i_] != '}'; skip()) {
        Span key = string();
        skip();
        ++i_;  // ':'
        Span val = value();
        v.members.emplace_back(key, std::move(val));
        skip();
        if (s_[i_] == ',') ++i_;
      }
      ++i_;
    } else if (s_[i_] == '[') {
      ++i_;
      for (skip(); s_[i_] != ']'; skip()) {
        v.elements.push_back(value());
        skip();
        if (s_[i_] == ',') ++i_;
      }
      ++i_;
    } else if (s_[i_] == '"') {
      return string();
    } else {
      while (i_ < s_.size() && std::string_view(",]} \t\r\n").find(s_[i_]) == std::string_view::npos) ++i_;
    }
    v.end = i_;
    return v;
  }

 private:
  Span string() {
    Span v;
    v.begin = i_++;
    while (s_[i_] != '"') i_ += s_[i_] == '\\' ? 2 : 1;
    v.end = ++i_;
    return v;
  }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  const std::string& s_;
  std::size_t i_ = 0;
};

struct Patch {
  std::size_t begin, end;
  std::string text;
};

// Collects the patches that turn `original` (laid out as `span`) into `migrated`; false when the change is
// structural (members or elements added or removed, a value changed kind).
bool collect_patches(const ordered_json& original, const ordered_json& migrated, const Span& span,
                     std::vector<Patch>& patches) {
  if (original.is_object() != migrated.is_object() || original.is_array() != migrated.is_array()) return false;
  if (original.is_object()) {
    if (original.size() != migrated.size() || span.members.size() != original.size()) return false;
    auto o = original.items().begin();
    auto m = migrated.items().begin();
    for (std::size_t k = 0; k < span.members.size(); ++k, ++o, ++m) {
      const auto& [key, value] = span.members[k];
      if (o.key() != m.key()) patches.push_back({key.begin, key.end, json(m.key()).dump()});
      if (!collect_patches(o.value(), m.value(), value, patches)) return false;
    }
    return true;
  }
  if (original.is_array()) {
    if (original.size() != migrated.size() || span.elements.size() != original.size()) return false;
    for (std::size_t k = 0; k < original.size(); ++k)
      if (!collect_patches(original[k], migrated[k], span.elements[k], patches)) return false;
    return true;
  }
  if (original != migrated) {
    if (original.is_structured() || migrated.is_structured()) return false;
    patches.push_back({span.begin, span.end, scalar_text(migrated)});
  }
  return true;
}

// The original text with the migration's renames and new values patched in, or nullopt when the migration
// changed the structure.
std::optional<std::string> patched_text(const std::string& text, const ordered_json& original,
                                        const ordered_json& migrated) {
  const Span root = Scanner(text).value();
  std::vector<Patch> patches;
  if (!collect_patches(original, migrated, root, patches)) return std::nullopt;
  std::string out = text;
  for (auto p = patches.rbegin(); p != patches.rend(); ++p) out.replace(p->begin, p->end - p->begin, p->text);
  return out;
}

}  // namespace

std::string format_graph_text(const nlohmann::ordered_json& doc) {
  std::string out;
  write(out, doc, 0, "");
  return out + "\n";
}

int run_migrate(const std::vector<std::filesystem::path>& files, bool check_only) {
  int code = kExitOk;
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
      std::cerr << file.string() << ": cannot be read\n";
      code = kExitInvalid;
      continue;
    }
    std::stringstream text;
    text << in.rdbuf();
    const ordered_json original = ordered_json::parse(text.str(), nullptr, false);
    json doc = json::parse(text.str(), nullptr, false);
    if (doc.is_discarded()) {
      std::cerr << file.string() << ": not JSON\n";
      code = kExitInvalid;
      continue;
    }
    int from = 0;
    try {
      from = migrate_graph_document(doc);
    } catch (const std::exception& e) {
      std::cerr << file.string() << ": " << e.what() << "\n";
      code = kExitInvalid;
      continue;
    }
    if (from == kGraphFormatVersion) {
      std::cout << file.string() << ": at version " << kGraphFormatVersion << "\n";
      continue;
    }
    if (check_only) {
      std::cout << file.string() << ": version " << from << ", needs migrating to " << kGraphFormatVersion << "\n";
      code = kExitEvalFailed;
      continue;
    }
    const ordered_json ordered = in_original_order(original, doc);
    const std::string migrated = patched_text(text.str(), original, ordered).value_or(format_graph_text(ordered));
    const auto loaded = parse_graph(migrated);
    if (!loaded.ok())
      std::cerr << file.string() << ": migrated, but it does not load (orogen validate tells more):\n"
                << loaded.error_text();
    write_text_atomically(file, migrated);
    std::cout << file.string() << ": version " << from << " -> " << kGraphFormatVersion << "\n";
  }
  return code;
}

}  // namespace orogen::cli
