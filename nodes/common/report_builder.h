#pragma once
// The one way nodes build a Report: an ordered JSON object (keys stay in the order the node sets them, so
// related figures read together) dumped with an indent of 2; figures that are not finite become null, since
// JSON has no NaN or infinity.
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "graph/report.h"

namespace orogen {

using ReportJson = nlohmann::ordered_json;

// A figure: the number, or null when it is NaN or infinite.
inline ReportJson report_number(double v) { return std::isfinite(v) ? ReportJson(v) : ReportJson(nullptr); }

// The text of a report object.
inline std::string report_text(const ReportJson& object) { return object.dump(2); }

// A Report holding `text`, made by report_text (algorithms that return their report's text, e.g. for tests).
inline std::shared_ptr<Report> make_report(std::string text) {
  auto report = std::make_shared<Report>();
  report->json = std::move(text);
  return report;
}

// A Report holding `object`.
inline std::shared_ptr<Report> make_report(const ReportJson& object) { return make_report(report_text(object)); }

}  // namespace orogen
