// The servo calibration's report: DIR/report.json (what a program reads),
// DIR/report.md and the SVG plots (what a person reads).
// docs/calibration.md describes the fields.
#pragma once

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>

#include "analysis/calibration/servo_calibration.h"

namespace chainsim {

// an output file that cannot be written
struct ReportError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

nlohmann::ordered_json calibration_report_json(const ServoCalibration& c);

// report.md from the calibration and its report.json; bench_file and
// measured_file are named in it ("" bench file: the defaults)
std::string calibration_report_md(const ServoCalibration& c, const nlohmann::ordered_json& j,
                                  const std::string& bench_file, const std::string& measured_file);

// writes report.json, angle.svg, residual.svg, current.svg (with a current
// channel) and report.md to out_dir (which exists); throws ReportError
void write_calibration_report(const ServoCalibration& c, const std::string& bench_file,
                              const std::string& measured_file, const std::string& out_dir);

}  // namespace chainsim
