#include "graph/exec_context.h"

#include <algorithm>

namespace orogen {

ExecContext::ExecContext(const NodeType& type, std::string node_id, Domain domain, std::vector<PortValue> inputs,
                         std::vector<ParamValue> params)
    : type_(type),
      node_id_(std::move(node_id)),
      domain_(domain),
      inputs_(std::move(inputs)),
      params_(std::move(params)),
      outputs_(type.outputs.size()) {
  inputs_.resize(type.inputs.size());
  if (params_.size() != type.params.size())
    throw std::logic_error("ExecContext for '" + type.name + "': wrong number of parameter values");
}

std::size_t ExecContext::input_slot(std::string_view name, PortType expected) const {
  const int i = type_.input_index(name);
  if (i < 0) throw std::logic_error("node type '" + type_.name + "' has no input '" + std::string(name) + "'");
  if (type_.inputs[static_cast<std::size_t>(i)].type != expected)
    throw std::logic_error("input '" + std::string(name) + "' of '" + type_.name + "' read as the wrong type");
  return static_cast<std::size_t>(i);
}

std::size_t ExecContext::output_slot(std::string_view name, PortType expected) const {
  const int i = type_.output_index(name);
  if (i < 0) throw std::logic_error("node type '" + type_.name + "' has no output '" + std::string(name) + "'");
  if (type_.outputs[static_cast<std::size_t>(i)].type != expected)
    throw std::logic_error("output '" + std::string(name) + "' of '" + type_.name + "' set with the wrong type");
  return static_cast<std::size_t>(i);
}

std::size_t ExecContext::param_slot(std::string_view name) const {
  const int i = type_.param_index(name);
  if (i < 0) throw std::logic_error("node type '" + type_.name + "' has no parameter '" + std::string(name) + "'");
  return static_cast<std::size_t>(i);
}

bool ExecContext::output_requested(std::string_view name) const {
  const int i = type_.output_index(name);
  if (i < 0) throw std::logic_error("node type '" + type_.name + "' has no output '" + std::string(name) + "'");
  return requested_outputs_.empty() || requested_outputs_.at(static_cast<std::size_t>(i));
}

int ExecContext::enum_index(std::string_view name) const {
  const auto& decl = type_.params[param_slot(name)];
  const auto& value = param<std::string>(name);
  const auto it = std::find(decl.choices.begin(), decl.choices.end(), value);
  return it == decl.choices.end() ? -1 : static_cast<int>(it - decl.choices.begin());
}

void ExecContext::progress(double fraction) const {
  if (on_progress_) on_progress_(std::clamp(fraction, 0.0, 1.0));
}

std::filesystem::path ExecContext::output_path(std::string_view param_name) const {
  try {
    return resolve_output_path(output_policy_, param<std::string>(param_name));
  } catch (const OutputPathError& e) {
    throw NodeError(e.what());
  }
}

std::filesystem::path ExecContext::input_path(std::string_view param_name) const {
  return resolve_input_path(input_dir_, param<std::string>(param_name));
}

}  // namespace orogen
