// Values from the command line: `--define NAME=EXPR` sets what the built-in `param("NAME",
// DEFAULT)` returns. The table is filled once per command and handed to the interpreter
// (LoadOptions::params), which passes it to built-in calls.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "lang/builtins.h"
#include "lang/value.h"

namespace wsd::lang {

class ParamTable {
public:
    void set(const std::string& name, Value value) { values_[name] = std::move(value); }
    bool empty() const { return values_.empty(); }
    // The value given for `name` (null if none); marks it read.
    const Value* read(const std::string& name) const;
    // The names that no `param` call read, in name order.
    std::vector<std::string> unread() const;

private:
    std::map<std::string, Value> values_;
    mutable std::set<std::string> read_;
};

// Evaluates the EXPR of a --define with only the built-ins in scope (`clock` and `frame` those of
// `time`). The value must be a number,
// bool, string or vector (values that carry no source position of their own); otherwise nullopt
// and `error` says why.
std::optional<Value> evaluate_define(const std::string& expr, std::string& error,
                                     const AnimationTime& time = {});

// The built-in `param(NAME, DEFAULT)`: the call's table's value for NAME, else DEFAULT; a
// value whose type differs from DEFAULT's is an error at the call.
std::optional<Value> builtin_param(const CallContext& c);

}  // namespace wsd::lang
