// The parameter table (parameters.h) against the validation that enforces it: every default is
// accepted, every range's ends are where validate() puts them, every choice is accepted.
#include <cmath>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "hope/parameters.h"

namespace hope {
namespace {

bool accepted(const ParameterSpec& spec, double value) {
  PipelineOptions options;
  spec.set(options, value);
  try {
    validate(options);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

// A step just past `end` (relative, so that it shows at any magnitude).
double past(double end, double direction) {
  return end + direction * std::max(1e-9, std::fabs(end) * 1e-6);
}

TEST(Parameters, EveryRangeEndsWhereValidationEndsIt) {
  std::size_t checked_ends = 0;
  for (const ParameterSpec& spec : pipelineParameters()) {
    SCOPED_TRACE(spec.name);
    ASSERT_TRUE(spec.set) << "every parameter can be set";
    if (spec.type == ParameterSpec::Type::kChoice) {
      EXPECT_FALSE(spec.choices.empty());
      for (std::size_t k = 0; k < spec.choices.size(); ++k) EXPECT_TRUE(accepted(spec, k));
      continue;
    }
    EXPECT_TRUE(accepted(spec, spec.default_value)) << "the default is accepted";
    EXPECT_LE(spec.min, spec.default_value);
    EXPECT_LE(spec.default_value, spec.max);
    if (spec.type == ParameterSpec::Type::kBool) {
      EXPECT_TRUE(accepted(spec, 0));
      EXPECT_TRUE(accepted(spec, 1));
      continue;
    }
    const double step = spec.type == ParameterSpec::Type::kInt ? 1.0 : 0.0;
    if (std::isfinite(spec.min)) {
      if (spec.min_excluded) {
        EXPECT_FALSE(accepted(spec, spec.min)) << "the range is (min, max]";
        EXPECT_TRUE(accepted(spec, past(spec.min, +1)));
      } else {
        EXPECT_TRUE(accepted(spec, spec.min));
        EXPECT_FALSE(accepted(spec, step > 0 ? spec.min - step : past(spec.min, -1)));
      }
      ++checked_ends;
    }
    if (std::isfinite(spec.max)) {
      EXPECT_TRUE(accepted(spec, spec.max));
      EXPECT_FALSE(accepted(spec, step > 0 ? spec.max + step : past(spec.max, +1)));
      ++checked_ends;
    }
  }
  EXPECT_GE(checked_ends, 20u);
}

TEST(Parameters, NamesAndOptionsAreUniqueAndEveryOneIsExplained) {
  std::set<std::string> names, options;
  for (const ParameterSpec& spec : pipelineParameters()) {
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
    if (!spec.option.empty()) {
      EXPECT_TRUE(options.insert(spec.option).second) << spec.option;
    }
    EXPECT_FALSE(spec.doc.empty()) << spec.name;
    EXPECT_FALSE(spec.stage.empty()) << spec.name;
  }
  EXPECT_GE(names.size(), 16u);
}

}  // namespace
}  // namespace hope
