#include "evaluator/run_node.h"

#include <stdexcept>

#include "graph/exec_context.h"
#include "graph/graph.h"
#include "graph/registry.h"

namespace orogen {

namespace {

const NodeType& find_type(const std::string& type_name) {
  const NodeType* type = NodeRegistry::instance().find(type_name);
  if (!type) throw std::logic_error("run_node: unknown node type '" + type_name + "'");
  return *type;
}

// `requested`: by output index, empty for all.
NodeRun run(const NodeType* type, const std::string& type_name, const Domain& domain,
            const std::map<std::string, ParamValue>& params, const std::map<std::string, PortValue>& inputs,
            const OutputPolicy& output, const CancelToken* cancel, std::function<void(double)> on_progress,
            std::vector<bool> requested) {
  std::vector<ParamValue> values;
  for (const auto& decl : type->params) {
    const auto it = params.find(decl.name);
    if (it == params.end()) {
      values.push_back(decl.default_value);
      continue;
    }
    if (auto why = decl.check(it->second); !why.empty()) throw GraphError(type_name + "." + decl.name + ": " + why);
    values.push_back(it->second);
  }
  for (const auto& [name, v] : params)
    if (!type->find_param(name))
      throw std::logic_error("run_node: '" + type_name + "' has no parameter '" + name + "'");
  std::vector<PortValue> in(type->inputs.size());
  for (const auto& [name, v] : inputs) {
    const int i = type->input_index(name);
    if (i < 0) throw std::logic_error("run_node: '" + type_name + "' has no input '" + name + "'");
    if (has_value(v) && port_type_of(v) != type->inputs[static_cast<std::size_t>(i)].type)
      throw std::logic_error("run_node: input '" + name + "' has the wrong type");
    in[static_cast<std::size_t>(i)] = v;
  }
  for (std::size_t i = 0; i < type->inputs.size(); ++i)
    if (!type->inputs[i].optional && !has_value(in[i]))
      throw NodeError("required input '" + type->inputs[i].name + "' is not connected");
  if (auto why = check_domain(domain); !why.empty()) throw NodeError(why);
  ExecContext ctx(*type, type_name, domain, std::move(in), std::move(values));
  ctx.set_output_policy(output);
  ctx.set_cancel_token(cancel);
  if (on_progress) ctx.set_progress_callback(std::move(on_progress));
  ctx.set_requested_outputs(requested);
  type->execute(ctx);
  // The same contract as in a graph: every requested output is set.
  for (std::size_t i = 0; i < type->outputs.size(); ++i)
    if ((requested.empty() || requested[i]) && !has_value(ctx.outputs()[i]))
      throw NodeError("the node did not set its output '" + type->outputs[i].name + "'");
  return NodeRun{std::move(ctx.outputs())};
}

}  // namespace

NodeRun run_node(const std::string& type_name, const Domain& domain, const std::map<std::string, ParamValue>& params,
                 const std::map<std::string, PortValue>& inputs, const OutputPolicy& output, const CancelToken* cancel,
                 std::function<void(double)> on_progress) {
  return run(&find_type(type_name), type_name, domain, params, inputs, output, cancel, std::move(on_progress), {});
}

NodeRun run_node_for_outputs(const std::vector<std::string>& outputs, const std::string& type_name,
                             const Domain& domain, const std::map<std::string, ParamValue>& params,
                             const std::map<std::string, PortValue>& inputs) {
  const NodeType& type = find_type(type_name);
  std::vector<bool> requested(type.outputs.size(), false);
  for (const auto& name : outputs) {
    const int i = type.output_index(name);
    if (i < 0) throw std::logic_error("run_node: '" + type_name + "' has no output '" + name + "'");
    requested[static_cast<std::size_t>(i)] = true;
  }
  return run(&type, type_name, domain, params, inputs, {}, nullptr, {}, std::move(requested));
}

}  // namespace orogen
