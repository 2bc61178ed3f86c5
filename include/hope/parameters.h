// Every parameter of the frame pipeline (frame_pipeline.h), defined once: its name (the
// nodelet's, config/hope.yaml's and hope.Pipeline's keyword), hope_extract's option, type,
// default (read from PipelineOptions), accepted range, unit, the stage that reads it, whether
// the nodelet takes it live (dynamic_reconfigure), and what it does. test_parameters.cpp holds
// validate() to the ranges; test/python/test_parameters_agree.py holds cfg/Hope.cfg,
// config/hope.yaml, docs/ros.md, hope_extract --help and hope.Pipeline to the whole table.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "hope/frame_pipeline.h"

namespace hope {

struct ParameterSpec {
  enum class Type { kDouble, kInt, kBool, kChoice };
  std::string name;    // nodelet parameter, hope.yaml key, hope.Pipeline keyword
  std::string option;  // hope_extract's option ("" when the CLI takes it otherwise)
  Type type = Type::kDouble;
  // Numbers and booleans (0 / 1): the default and the accepted range, both ends included
  // (infinite ends: no limit). Choices: the default and the accepted values.
  double default_value = 0, min = 0, max = 0;
  bool min_excluded = false;  // the range is (min, max]
  std::string default_choice;
  std::vector<std::string> choices;
  std::string unit;   // "m", "m²", "s", "deg", "" for none
  std::string stage;  // the stage or part of the pipeline that reads it
  bool live = false;  // the nodelet takes a new value while running (cfg/Hope.cfg)
  std::string doc;
  // Sets the value on `options` (numbers and booleans; choices by index into `choices`).
  std::function<void(PipelineOptions&, double)> set;
};

// The table, defaults from PipelineOptions().
const std::vector<ParameterSpec>& pipelineParameters();

}  // namespace hope
