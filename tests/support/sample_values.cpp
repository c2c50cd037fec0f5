#include "support/sample_values.h"

#include <exception>
#include <string>

#include "evaluator/run_node.h"
#include "graph/registry.h"

namespace orogen::test {

std::map<PortType, PortValue> sample_values(const HeightfieldPtr& field, const OutputPolicy& policy) {
  const Domain& d = field->domain;
  std::map<PortType, PortValue> values{{PortType::Heightfield, PortValue(field)}};
  for (int pass = 0; pass < 3; ++pass) {
    for (const NodeType* type : NodeRegistry::instance().all()) {
      if (type->writes_files) continue;
      std::map<std::string, PortValue> inputs;
      bool feasible = true;
      for (const auto& in : type->inputs) {
        if (auto it = values.find(in.type); it != values.end())
          inputs[in.name] = it->second;
        else if (!in.optional)
          feasible = false;
      }
      if (!feasible) continue;
      bool wanted = false;
      for (const auto& out : type->outputs) wanted = wanted || !values.count(out.type);
      if (!wanted) continue;
      try {
        const auto run = run_node(type->name, d, {}, inputs, policy);
        for (std::size_t k = 0; k < type->outputs.size(); ++k)
          if (!values.count(type->outputs[k].type) && has_value(run.outputs[k]))
            values[type->outputs[k].type] = run.outputs[k];
      } catch (const std::exception&) {}
    }
  }
  return values;
}

}  // namespace orogen::test
