#include "evaluator/node_keys.h"

#include <filesystem>
#include <system_error>

#include "graph/node_type.h"

namespace orogen {

ResolvedLink resolve_link(const Graph& graph, const Node& node, const PortDecl& port) {
  ResolvedLink r;
  const auto it = node.inputs.find(port.name);
  if (it == node.inputs.end()) return r;
  const PortRef& from = it->second;
  r.source = graph.find(from.node);
  if (!r.source) {
    r.error = "input '" + port.name + "' is linked to missing node '" + from.node + "'";
    return r;
  }
  r.output = r.source->type->output_index(from.port);
  if (r.output < 0) {
    r.error = "input '" + port.name + "' is linked to " + from.str() + ", but node '" + from.node + "' (" +
              r.source->type->name + ") has no output '" + from.port + "'";
    return r;
  }
  const PortType type = r.source->type->outputs[static_cast<std::size_t>(r.output)].type;
  if (type != port.type)
    r.error = "input '" + port.name + "' takes " + std::string(to_string(port.type)) + " but is linked to " +
              from.str() + " which is " + std::string(to_string(type));
  return r;
}

const NodeKeyInfo& NodeKeys::of(const Node& node) {
  if (const auto it = done_.find(&node); it != done_.end()) return it->second;
  const std::string& id = node.id;
  const NodeType& type = *node.type;
  NodeKeyInfo info;
  auto finish = [&]() -> const NodeKeyInfo& {
    visiting_.erase(&node);
    return done_[&node] = std::move(info);
  };
  if (!visiting_.insert(&node).second) {
    // Only reachable for graphs that bypassed Graph::connect's cycle check.
    info.error = "the node is part of a cycle";
    return done_.emplace(&node, info).first->second;
  }

  for (const auto& [port, link] : node.inputs)
    if (!type.find_input(port)) {
      info.error = "input '" + port + "' is linked, but node type '" + type.name + "' has no input '" + port + "'";
      return finish();
    }

  KeyHasher h;
  h.add(std::string_view(kNodeKeySchema)).add(std::string_view(type.name)).add(std::int64_t{type.version});

  // Effective values (explicit or default) without copying them.
  std::vector<const ParamValue*> params(type.params.size());
  for (std::size_t i = 0; i < type.params.size(); ++i) {
    const ParamDecl& decl = type.params[i];
    const auto it = node.params.find(decl.name);
    params[i] = it != node.params.end() ? &it->second : &decl.default_value;
    if (auto why = decl.check(*params[i]); !why.empty() && info.error.empty())
      info.error = "parameter '" + decl.name + "': " + why;
    h.add(std::string_view(decl.name)).add(*params[i]);
  }

  for (const PortDecl& port : type.inputs) {
    h.add(std::string_view(port.name));
    const ResolvedLink link = resolve_link(graph_, node, port);
    if (!link.error.empty()) {
      info.error = link.error;
      return finish();
    }
    if (!link.source) {
      if (!port.optional && info.error.empty()) info.error = "required input '" + port.name + "' is not connected";
      h.add(false);  // the fixed "absent" marker
      continue;
    }
    const NodeKeyInfo& up = of(*link.source);
    if (!up.key) {
      info.blocked_by = up.error.empty() ? up.blocked_by : link.source->id;
      if (info.blocked_by == id) {  // a cycle came back to this node
        info.blocked_by.clear();
        info.error = "the node is part of a cycle";
      }
      return finish();
    }
    h.add(true).add(*up.key).add(
        std::string_view(link.source->type->outputs[static_cast<std::size_t>(link.output)].name));
  }

  if (type.domain_independent) {
    h.add(false);
  } else {
    const Domain* own = &domain_;
    if (node_domains_)
      if (const auto it = node_domains_->find(id); it != node_domains_->end()) own = &it->second;
    h.add(true).add(*own);
  }

  // Files a node reads (path parameters that are not outputs) are data too: their size and modification time
  // join the key, so a file changed by another tool is read again instead of served stale from the cache.
  for (std::size_t i = 0; i < type.params.size(); ++i) {
    const ParamDecl& decl = type.params[i];
    if (decl.type != ParamType::Path || decl.output_file) continue;
    const auto* value = std::get_if<std::string>(params[i]);
    if (!value || value->empty()) continue;
    std::error_code ec;
    const std::filesystem::path path = resolve_input_path(graph_.directory, *value);
    // The file itself, not just the text: the same relative path next to another graph file is another file.
    const auto absolute = std::filesystem::absolute(path, ec);
    h.add(std::string_view((ec ? path : absolute).lexically_normal().generic_string()));
    ec.clear();
    const auto size = std::filesystem::file_size(path, ec);
    const auto mtime = ec ? std::filesystem::file_time_type{} : std::filesystem::last_write_time(path, ec);
    if (ec) {
      h.add(false);  // missing or unreadable: the node fails when it runs, and failures are never cached
    } else {
      h.add(true).add(std::uint64_t{size}).add(std::int64_t{mtime.time_since_epoch().count()});
    }
  }

  if (type.writes_files) {
    // Where the files go is part of what the node does: another output directory is another result.
    for (std::size_t i = 0; i < type.params.size(); ++i) {
      if (!type.params[i].output_file) continue;
      const auto* value = std::get_if<std::string>(params[i]);
      if (!value) continue;
      try {
        std::error_code ec;
        auto path = resolve_output_path(output_, *value);
        auto absolute = std::filesystem::absolute(path, ec);
        h.add(true).add(std::string_view((ec ? path : absolute).lexically_normal().generic_string()));
      } catch (const OutputPathError& e) {
        h.add(false).add(std::string_view(e.what()));  // the node will fail with this message when it runs
      }
    }
  }

  info.key = h.finish();
  return finish();
}

}  // namespace orogen
