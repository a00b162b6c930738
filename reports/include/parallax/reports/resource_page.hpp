// The resource model's calibration as a self-contained HTML page (`parallax fit-resources --html`):
// per resource an SVG scatter of predicted (leave-one-family-out) against published on log axes
// with the y = x line and the +-20 % and +-40 % bands, the error summary, and a table of every row
// (rows the library cannot describe listed with the reason).
#pragma once

#include <string>

#include "parallax/resources/fit.hpp"

namespace parallax::reports {

std::string resource_model_page(const res::FitResult& fit, res::Flavour flavour, const std::string& points_path);

}  // namespace parallax::reports
