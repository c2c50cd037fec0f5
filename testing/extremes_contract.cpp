// The extremes contract (testing/contracts.h): every parameter at the ends of its range, and non-finite
// inputs, on small odd domains. The outcome of each run is a result (finite where the inputs were), a
// NodeError with a message, or a run that stops soon after it is cancelled; anything else is a bug.
#include <cxxabi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>
#include <typeinfo>

#include <unistd.h>

#include "evaluator/run_node.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "testing/contracts.h"

namespace orogen::contracts {
namespace {

using Clock = std::chrono::steady_clock;
using Seconds = std::chrono::duration<double>;

// Failures listed per type: a node broken at one extreme is usually broken on every domain; the rest are counted.
constexpr std::size_t kMaxListed = 8;

std::string type_name_of(const std::type_info& t) {
  int status = 0;
  char* name = abi::__cxa_demangle(t.name(), nullptr, nullptr, &status);
  std::string out = status == 0 && name ? name : t.name();
  std::free(name);
  return out;
}

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g s", s);
  return buf;
}

HeightfieldPtr non_finite_field(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  const float special[] = {std::numeric_limits<float>::quiet_NaN(),
                           std::numeric_limits<float>::infinity(),
                           -std::numeric_limits<float>::infinity(),
                           3e38f,
                           -3e38f,
                           0.0f,
                           1e-38f};
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = special[static_cast<std::size_t>(i * 3 + j) % 7];
  return h;
}

HeightfieldPtr all_nan_field(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  for (auto& v : h->data) v = std::numeric_limits<float>::quiet_NaN();
  return h;
}

// Where an output of samples holds a NaN or an infinity, described; empty when it is all finite (or has no
// samples: points, meshes, reports).
std::string first_non_finite(const PortValue& v) {
  auto where = [](float x, int i, int j) {
    return std::string(std::isnan(x) ? "NaN" : "an infinity") + " at sample (" + std::to_string(i) + ", " +
           std::to_string(j) + ")";
  };
  if (const auto* f = std::get_if<HeightfieldPtr>(&v)) {
    const auto& h = **f;
    for (int j = 0; j < h.domain.height(); ++j)
      for (int i = 0; i < h.domain.width(); ++i)
        if (!std::isfinite(h.at(i, j))) return where(h.at(i, j), i, j);
  } else if (const auto* img = std::get_if<ImagePtr>(&v)) {
    const auto& m = **img;
    for (int j = 0; j < m.domain.height(); ++j)
      for (int i = 0; i < m.domain.width(); ++i)
        for (int c = 0; c < m.channels; ++c)
          if (!std::isfinite(m.pixel(i, j)[c])) return where(m.pixel(i, j)[c], i, j) + " channel " + std::to_string(c);
  }
  return {};
}

// One run on a worker thread, cancelled after o.run_seconds; the state is shared so that a node that ignores
// the cancel can be abandoned without leaving the worker with dangling references.
struct Run {
  std::string type;
  Domain domain;
  std::map<std::string, ParamValue> params;
  std::map<std::string, PortValue> inputs;
  OutputPolicy output;
  CancelToken cancel;
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  bool abandoned = false;  // the sweep stopped waiting: the worker counts itself out of g_left_running
  std::optional<NodeRun> result;
  std::exception_ptr error;
};

std::atomic<int> g_left_running{0};

enum class Outcome { Result, Error, Cancelled, Failed, Abandoned };

struct Sweep {
  const NodeType& type;
  const ExtremesOptions& o;
  ContractResult& r;
  Clock::time_point start = Clock::now();
  int runs = 0, results = 0, errors = 0, cancelled = 0, unlisted = 0;

  void fail(std::string why) {
    if (r.failures.size() < kMaxListed)
      r.failures.push_back(std::move(why));
    else
      ++unlisted;
  }

  Outcome run(const std::string& label, const Domain& d, const std::map<std::string, ParamValue>& params,
              const std::map<std::string, PortValue>& inputs, bool finite_inputs) {
    ++runs;
    std::shared_ptr<Run> st;
    double first_latency = 0.0;
    for (int attempt = 0; attempt < 2; ++attempt) {
      st = std::make_shared<Run>();
      st->type = type.name;
      st->domain = d;
      st->params = params;
      st->inputs = inputs;
      st->output = o.output;
      std::thread worker([st] {
        try {
          st->result = run_node(st->type, st->domain, st->params, st->inputs, st->output, &st->cancel);
        } catch (...) {
          st->error = std::current_exception();
        }
        std::lock_guard lock(st->m);
        st->done = true;
        if (st->abandoned) --g_left_running;
        st->cv.notify_all();
      });
      std::unique_lock lock(st->m);
      double latency = 0.0;
      if (!st->cv.wait_for(lock, Seconds(o.run_seconds), [&] { return st->done; })) {
        const auto cancelled_at = Clock::now();
        st->cancel.cancel();
        // Past the bound is late; past a few times the bound the node is left running and the sweep stops.
        if (!st->cv.wait_for(lock, Seconds(4.0 * o.cancel_bound), [&] { return st->done; })) {
          st->abandoned = true;
          ++g_left_running;
          lock.unlock();
          worker.detach();
          fail(label + ": still running " + seconds_text(4.0 * o.cancel_bound) +
               " after it was cancelled (left running; the remaining runs are skipped): poll "
               "ctx.check_cancelled() in every long loop");
          return Outcome::Abandoned;
        }
        latency = Seconds(Clock::now() - cancelled_at).count();
      }
      lock.unlock();
      worker.join();
      if (latency <= o.cancel_bound) break;
      // A loaded machine can delay one return; late twice in a row is the node's doing.
      if (attempt == 0) {
        first_latency = latency;
        continue;
      }
      fail(label + ": returned " + seconds_text(first_latency) + ", then " + seconds_text(latency) +
           " after it was cancelled, more than the bound of " + seconds_text(o.cancel_bound) +
           ": poll ctx.check_cancelled() more often");
    }
    if (!st->error) {
      ++results;
      if (!finite_inputs) return Outcome::Result;
      for (std::size_t k = 0; k < st->result->outputs.size() && k < type.outputs.size(); ++k)
        if (const auto where = first_non_finite(st->result->outputs[k]); !where.empty()) {
          fail(label + ": output '" + type.outputs[k].name + "' has " + where +
               " although every input was finite: guard the division, logarithm or power, or refuse the value "
               "with a NodeError naming the parameter");
          return Outcome::Failed;
        }
      return Outcome::Result;
    }
    try {
      std::rethrow_exception(st->error);
    } catch (const Cancelled&) {
      ++cancelled;
      return Outcome::Cancelled;
    } catch (const NodeError& e) {  // GraphError is not one: run_node's parameter check is passed by design
      ++errors;
      if (std::string(e.what()).size() < 5) {
        fail(label + ": a NodeError without a message: say what is wrong and which parameter to change");
        return Outcome::Failed;
      }
      return Outcome::Error;
    } catch (const std::exception& e) {
      fail(label + ": threw " + type_name_of(typeid(e)) + " (\"" + e.what() +
           "\"), not a NodeError: refuse the value with a NodeError naming the parameter, or handle it");
    } catch (...) {
      fail(label + ": threw something that is not a std::exception");
    }
    return Outcome::Failed;
  }

  bool out_of_time() const { return Clock::now() - start > Seconds(o.budget_seconds); }
};

// The inputs of `type` on `d`: the kit's generated values, else o.inputs; nullopt if a required one is missing
// (named in `missing`).
std::optional<std::map<std::string, PortValue>> inputs_for(const NodeType& type, const Domain& d,
                                                           const std::map<PortType, PortValue>& extra,
                                                           std::string& missing) {
  std::map<std::string, PortValue> in;
  for (const auto& port : type.inputs) {
    auto v = contract_input(port, d);
    if (std::holds_alternative<std::monostate>(v))
      if (const auto it = extra.find(port.type); it != extra.end()) v = it->second;
    if (std::holds_alternative<std::monostate>(v)) {
      if (!port.optional) {
        missing = port.name + " (" + std::string(to_string(port.type)) + ")";
        return std::nullopt;
      }
      continue;
    }
    in[port.name] = std::move(v);
  }
  return in;
}

std::map<std::string, PortValue> with_fields(const NodeType& type, std::map<std::string, PortValue> in,
                                             const HeightfieldPtr& field) {
  for (const auto& port : type.inputs)
    if (port.type == PortType::Heightfield && in.count(port.name)) in[port.name] = PortValue(field);
  return in;
}

}  // namespace

int runs_left_running() { return g_left_running.load(); }

std::vector<std::pair<std::string, ParamValue>> extreme_values(const ParamDecl& p) {
  std::vector<std::pair<std::string, ParamValue>> out;
  const double lo = p.min.value_or(-1e6), hi = p.max.value_or(1e6);
  switch (p.type) {
    case ParamType::Float:
      out.push_back({"min", lo});
      out.push_back({"max", hi});
      break;
    case ParamType::Int:
      out.push_back({"min", static_cast<std::int64_t>(lo)});
      out.push_back({"max", static_cast<std::int64_t>(hi)});
      break;
    case ParamType::Vec2:
      out.push_back({"min", glm::dvec2(lo)});
      out.push_back({"max", glm::dvec2(hi)});
      out.push_back({"mixed", glm::dvec2(lo, hi)});
      break;
    case ParamType::Vec3:
      out.push_back({"min", glm::dvec3(lo)});
      out.push_back({"max", glm::dvec3(hi)});
      break;
    case ParamType::Bool:
      out.push_back({"false", false});
      out.push_back({"true", true});
      break;
    case ParamType::Enum:
      for (const auto& c : p.choices) out.push_back({c, c});
      break;
    case ParamType::Seed:
      out.push_back({"max", std::numeric_limits<std::uint64_t>::max()});
      break;
    case ParamType::Curve: {
      CurveValue steep;
      steep.points = {{-1e6, 1e6}, {-1e6 + 1e-9, -1e6}, {1e6, 1e6}};
      out.push_back({"steep", steep});
      break;
    }
    default:
      break;  // colors, strings, paths, gradients, tables: their defaults
  }
  std::erase_if(out, [&](const auto& e) { return !p.check(e.second).empty(); });  // what a graph could not hold
  return out;
}

std::vector<ExtremesDomain> extremes_domains() {
  return {
      {"non-square 23x7", Domain::from_extent({0, 0}, {300, 90}, {23, 7}), true},
      {"tiny spacing", Domain::from_extent({0, 0}, {3.2e-5, 3.2e-5}, {17, 17}), true},
      {"huge coordinates", Domain::from_extent({9e11, -9e11}, {5000, 5000}, {17, 17}), false},
      {"2x2", Domain::from_extent({0, 0}, {10, 10}, {2, 2}), false},
  };
}

ContractResult check_extremes(const NodeType& type, const ExtremesOptions& options) {
  ContractResult r{"extremes", Status::Passed, {}, ""};
  ExtremesOptions o = options;
  // A writer writes into a scratch folder of its own unless the caller chose one.
  std::filesystem::path scratch;
  if (type.writes_files && o.output.output_dir == OutputPolicy{}.output_dir) {
    scratch =
        std::filesystem::temp_directory_path() / ("orogen-extremes-" + std::to_string(::getpid()) + "-" + type.name);
    o.output.output_dir = scratch;
  }
  Sweep s{type, o, r};
  bool stopped = false, abandoned = false, any_domain = false;
  std::string missing;
  for (const auto& dom : o.domains.empty() ? extremes_domains() : o.domains) {
    if (stopped || abandoned) break;
    const auto extra = o.inputs ? o.inputs(dom.domain) : std::map<PortType, PortValue>{};
    const auto inputs = inputs_for(type, dom.domain, extra, missing);
    if (!inputs) continue;
    any_domain = true;
    const std::string where = type.name + " on the " + dom.name + " domain";
    const bool fields = std::any_of(type.inputs.begin(), type.inputs.end(),
                                    [&](const PortDecl& p) { return p.type == PortType::Heightfield; });
    // Finite inputs, then (where the node reads fields) fields of NaN, infinities and extreme floats, then
    // (for the defaults) fields of NaN only.
    enum class In { Finite, NonFinite, AllNaN };
    auto go = [&](const std::string& label, const std::map<std::string, ParamValue>& params, In in) {
      if (abandoned || (in != In::Finite && !fields)) return;
      if (s.out_of_time()) {
        stopped = true;
        return;
      }
      auto run_inputs = *inputs;
      std::string what = label;
      if (in == In::NonFinite) {
        run_inputs = with_fields(type, run_inputs, non_finite_field(dom.domain));
        what += ", non-finite inputs";
      } else if (in == In::AllNaN) {
        run_inputs = with_fields(type, run_inputs, all_nan_field(dom.domain));
        what += ", all-NaN inputs";
      }
      abandoned = s.run(what, dom.domain, params, std::move(run_inputs), in == In::Finite) == Outcome::Abandoned;
    };
    for (In in : {In::Finite, In::NonFinite, In::AllNaN}) go(where + ", defaults", {}, in);
    if (!dom.parameter_extremes) continue;
    for (const auto& p : type.params) {
      if (p.output_file || p.type == ParamType::Path) continue;
      for (const auto& [end, value] : extreme_values(p)) {
        const std::string label = where + ", " + p.name + " = " + end + " (" + describe(value) + ")";
        go(label, {{p.name, value}}, In::Finite);
        go(label, {{p.name, value}}, In::NonFinite);
      }
    }
  }
  if (!scratch.empty()) {
    std::error_code ec;
    std::filesystem::remove_all(scratch, ec);
  }
  if (!any_domain) {
    r.status = Status::Skipped;
    r.note = "the kit cannot generate input " + missing;
    return r;
  }
  r.note = std::to_string(s.runs) + " runs: " + std::to_string(s.results) + " results, " + std::to_string(s.errors) +
           " errors, " + std::to_string(s.cancelled) + " cancelled";
  if (stopped) r.note += " (stopped at the time budget of " + seconds_text(o.budget_seconds) + ")";
  if (s.unlisted > 0) r.failures.push_back("... and " + std::to_string(s.unlisted) + " more failing runs");
  if (!r.failures.empty()) r.status = Status::Failed;
  return r;
}

}  // namespace orogen::contracts
