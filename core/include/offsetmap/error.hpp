#pragma once
#include <stdexcept>
#include <string>

namespace offsetmap {

// Every user-facing failure (bad file, bad parameter, no device, kernel build failure) is an Error
// whose what() is a complete sentence naming the file, parameter or device concerned.
class Error : public std::runtime_error {
  public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// "OpenCL error -5 (CL_OUT_OF_RESOURCES) in clEnqueueNDRangeKernel" for an OpenCL failure.
std::string describe_cl_error(int code);

}  // namespace offsetmap
