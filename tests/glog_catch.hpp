// glog's logging header in a Catch test: glog defines CHECK (an abort) and replaces Catch's
// where Catch comes first (the precompiled header). Include this instead of <glog/logging.h>:
// Catch's CHECK is defined again, as Catch defines it, so that a failed check is reported and
// the case goes on.
#pragma once

#include <glog/logging.h>

#include <catch2/catch.hpp>

#undef CHECK
#define CHECK(...) INTERNAL_CATCH_TEST("CHECK", Catch::ResultDisposition::ContinueOnFailure, __VA_ARGS__)
