#include "Usage.h"

#include <cstdio>

namespace wirenet {

std::string fmt(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.12g", v);
    return buf;
}

void requireLess(const std::string& small, double smallValue, const std::string& big, double bigValue) {
    if (!(smallValue <= bigValue))
        throw UsageError(small + " must be <= " + big + " (got " + fmt(smallValue) + " > " + fmt(bigValue) + ")");
}

}  // namespace wirenet
