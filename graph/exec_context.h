#pragma once
// What a node's execute function sees: its domain, inputs, parameters and outputs, plus progress,
// cancellation and the output-path rule. Filled in by the evaluator (or by a test) before execute runs.
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "graph/cancel.h"
#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/output_path.h"
#include "graph/param_value.h"
#include "graph/port_value.h"

namespace orogen {

// A node failed; the message is shown to the user with the node id.
struct NodeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ExecContext {
 public:
  ExecContext(const NodeType& type, std::string node_id, Domain domain, std::vector<PortValue> inputs,
              std::vector<ParamValue> params);

  const NodeType& type() const { return type_; }
  const std::string& node_id() const { return node_id_; }
  const Domain& domain() const { return domain_; }

  // The value on input `name`, or nullptr if the (optional) input is unconnected.
  template <class T>
  std::shared_ptr<const T> input(std::string_view name) const {
    const auto& v = inputs_.at(input_slot(name, PortTypeOf<T>::value));
    if (const auto* p = std::get_if<std::shared_ptr<const T>>(&v)) return *p;
    return nullptr;
  }
  // Like input(), but throws NodeError naming the port if nothing is connected.
  template <class T>
  std::shared_ptr<const T> require(std::string_view name) const {
    auto p = input<T>(name);
    if (!p) throw NodeError("input '" + std::string(name) + "' is not connected");
    return p;
  }

  // The parameter's value; T is the ParamValue alternative of its type (double, std::int64_t, ...).
  template <class T>
  const T& param(std::string_view name) const {
    return std::get<T>(params_.at(param_slot(name)));
  }
  // Index of an enum parameter's value among its choices.
  int enum_index(std::string_view name) const;

  // Whether anything uses output `name`: a consumer linked to it, or a caller that wants all the node's outputs
  // (a node requested directly). A node may skip the work behind an output nobody requested and leave it unset;
  // every requested output must be set. True for every output unless the evaluator said otherwise.
  bool output_requested(std::string_view name) const;

  template <class T>
  void set_output(std::string_view name, std::shared_ptr<const T> value) {
    outputs_.at(output_slot(name, PortTypeOf<T>::value)) = std::move(value);
  }
  template <class T>
  void set_output(std::string_view name, std::shared_ptr<T> value) {
    set_output<T>(name, std::shared_ptr<const T>(std::move(value)));
  }

  // Reports progress in [0, 1]; cheap enough to call per row.
  void progress(double fraction) const;
  // Throws Cancelled when the run was cancelled. Long loops call it every few milliseconds of work.
  void check_cancelled() const {
    if (cancel_ && cancel_->cancelled()) throw Cancelled{};
  }
  bool cancelled() const { return cancel_ && cancel_->cancelled(); }

  // The file that output-path parameter `name` designates under the output policy; throws NodeError if the
  // rule refuses it. Writers then record what they wrote with record_written_file.
  std::filesystem::path output_path(std::string_view param_name) const;
  // The file that input-path parameter `name` designates: relative paths resolve against the graph file's
  // directory (set_input_dir), absolute ones stay.
  std::filesystem::path input_path(std::string_view param_name) const;
  void record_written_file(const std::filesystem::path& p) { written_files_.push_back(p); }

  // Evaluator hooks.
  void set_cancel_token(const CancelToken* token) { cancel_ = token; }
  void set_progress_callback(std::function<void(double)> cb) { on_progress_ = std::move(cb); }
  void set_output_policy(OutputPolicy policy) { output_policy_ = std::move(policy); }
  const OutputPolicy& output_policy() const { return output_policy_; }
  void set_input_dir(std::filesystem::path dir) { input_dir_ = std::move(dir); }
  const std::filesystem::path& input_dir() const { return input_dir_; }
  std::vector<PortValue>& outputs() { return outputs_; }
  // Which outputs are requested, by output index; empty (the default) requests all of them.
  void set_requested_outputs(std::vector<bool> requested) { requested_outputs_ = std::move(requested); }
  const std::vector<bool>& requested_outputs() const { return requested_outputs_; }
  const std::vector<std::filesystem::path>& written_files() const { return written_files_; }

 private:
  std::size_t input_slot(std::string_view name, PortType expected) const;
  std::size_t output_slot(std::string_view name, PortType expected) const;
  std::size_t param_slot(std::string_view name) const;

  const NodeType& type_;
  std::string node_id_;
  Domain domain_;
  std::vector<PortValue> inputs_;
  std::vector<ParamValue> params_;
  std::vector<PortValue> outputs_;
  std::vector<bool> requested_outputs_;  // empty: all
  const CancelToken* cancel_ = nullptr;
  std::function<void(double)> on_progress_;
  OutputPolicy output_policy_;
  std::filesystem::path input_dir_;
  std::vector<std::filesystem::path> written_files_;
};

}  // namespace orogen
