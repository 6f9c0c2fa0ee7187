#pragma once
// Errors the library reports. Only tools/ maps them to exit codes (docs/cli.md).
#include <stdexcept>
#include <string>

namespace decalcomp {

enum class ErrorKind {
    Usage = 2,   // bad command line
    Input = 3,   // unreadable or invalid input file, field, channel, texture
    Device = 4,  // OpenCL platform/device/build/runtime failure
    Output = 5,  // output cannot be written
};

class Error : public std::runtime_error {
public:
    Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
    ErrorKind kind() const { return kind_; }

private:
    ErrorKind kind_;
};

inline Error inputError(const std::string& message) { return Error(ErrorKind::Input, message); }
inline Error outputError(const std::string& message) { return Error(ErrorKind::Output, message); }
inline Error deviceError(const std::string& message) { return Error(ErrorKind::Device, message); }

}  // namespace decalcomp
