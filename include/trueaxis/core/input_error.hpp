#pragma once
// InputError: the one exception type for bad input (files, requests, options).
//
// Contract: what() reads "<source>:<line>: <field>: <message>" (line and field
// omitted when unknown), so a user can go straight to the offending spot.
// Every reader in trueaxis throws this, and the CLI turns it into a non-zero
// exit with that text on stderr.
#include <stdexcept>
#include <string>

namespace trueaxis {

class InputError : public std::runtime_error {
 public:
  InputError(std::string source, int line, std::string field, std::string message);
  InputError(std::string source, std::string message);

  const std::string& source() const { return source_; }
  int line() const { return line_; }  // 1-based; 0 when not tied to a line
  const std::string& field() const { return field_; }
  const std::string& message() const { return message_; }

 private:
  std::string source_;
  int line_ = 0;
  std::string field_;
  std::string message_;
};

}  // namespace trueaxis
