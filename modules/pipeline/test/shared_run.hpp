// A test suite whose tests share one pipeline run (the run is the expensive part).
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "photoscene/io.hpp"
#include "photoscene/pipeline.hpp"

namespace ps::test {

/// The base of a suite `Suite` (CRTP: each suite has its own run) whose SetUpTestSuite makes
/// dir_ and runs the pipeline into result_; both are released after the suite's last test, so
/// the next suite starts from an empty temp folder and the run's memory is given back.
template <class Suite>
class SharedRun : public ::testing::Test {
 protected:
  static void TearDownTestSuite() {
    result_.reset();
    dir_.reset();
  }
  static inline std::unique_ptr<io::TempDir> dir_;
  static inline std::unique_ptr<PipelineResult> result_;
};

}  // namespace ps::test
