#pragma once
// Errors that malformed input files cause in demsa::postprocess. The message always names the file, the line
// (when there is one) and the offending value: "pile.dump:12: ...".
#include <stdexcept>
#include <string>

namespace demsa::postprocess {

class ParseError : public std::runtime_error {
 public:
  ParseError(const std::string& file, long line, const std::string& message)
      : std::runtime_error(line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message),
        m_file(file),
        m_line(line),
        m_message(message) {}
  const std::string& file() const { return m_file; }
  long line() const { return m_line; }
  /// The message without the "file:line: " prefix.
  const std::string& message() const { return m_message; }

 private:
  std::string m_file;
  long m_line;
  std::string m_message;
};

/// Input that parses but cannot give the observable asked for (no particle on the pedestal, ...).
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace demsa::postprocess
