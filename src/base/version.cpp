// hbfriction — the library's version (hbf/version.hpp, generated from CMakeLists.txt).
#include "hbf/version.hpp"

namespace hbf {

const char* version() { return HBF_VERSION_STRING; }

}  // namespace hbf
