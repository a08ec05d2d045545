// The option table (api/option_table.h): every scalar option is one row, read by
// OptionsReader::read with the row's name, unit and bounds, and echoed in the row's unit. The
// OpenAPI side of the same rows is tested in tests/service/test_options_contract.cpp.

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/option_table.h"
#include "api/options_reader.h"

using nlohmann::json;
using namespace rollgap::api;

namespace {

// A value just outside each end of `range` (the end itself where it is open).
std::vector<double> outside(const Interval& range, bool integer) {
    const auto step = [integer](double at) {
        return integer ? 1.0 : std::max(std::fabs(at) * 1e-3, 1e-300);
    };
    return {range.min_open ? range.min : range.min - step(range.min),
            range.max_open ? range.max : range.max + step(range.max)};
}

// Reads the member `id` of `options` into a target of the row's type; the errors recorded.
FieldErrors read_row(const Option& row, const json& options, double& number, int& integer,
                     bool& flag) {
    FieldErrors errors;
    const std::string_view name = row.name;
    const std::array<std::string_view, 1> known{name};
    const OptionsReader reader(options, "/options", known, errors);
    switch (row.type) {
        case OptionType::number: reader.read(row.id, number); break;
        case OptionType::integer: reader.read(row.id, integer); break;
        case OptionType::boolean: reader.read(row.id, flag); break;
    }
    return errors;
}

}  // namespace

TEST_CASE("option table: one row per id, in order, each with a description") {
    REQUIRE(option_rows().size() == option_names.size());
    for (std::size_t i = 0; i < option_rows().size(); ++i) {
        const Option& row = option_rows()[i];
        CAPTURE(row.name);
        CHECK(static_cast<std::size_t>(row.id) == i);
        CHECK(&option(row.id) == &row);
        CHECK(row.name == option_name(row.id));
        CHECK(!row.description.empty());
        if (row.type != OptionType::boolean) CHECK(row.range.min < row.range.max);
        if (row.type == OptionType::integer) CHECK(row.unit.code == "1");
    }
}

TEST_CASE("option table: a component holds each member name once, and every row is in one") {
    std::set<OptionId> used;
    std::set<std::string_view> schemas;
    for (const OptionComponent& component : option_components()) {
        CAPTURE(component.schema);
        CHECK(schemas.insert(component.schema).second);
        std::set<std::string_view> names;
        for (const OptionId id : component.members) {
            CHECK(names.insert(option_name(id)).second);
            used.insert(id);
        }
    }
    CHECK(used.size() == option_rows().size());
}

TEST_CASE(
    "option table: the reader enforces each row's bounds and type, naming pointer, bound and "
    "unit, and stores SI") {
    for (const Option& row : option_rows()) {
        CAPTURE(row.name);
        const std::string pointer = "/options/" + std::string(row.name);
        double number = -1.0;
        int integer = -1;
        bool flag = false;
        if (row.type == OptionType::boolean) {
            CHECK(read_row(row, {{row.name, true}}, number, integer, flag).empty());
            CHECK(flag);
            const FieldErrors errors = read_row(row, {{row.name, 1}}, number, integer, flag);
            REQUIRE(errors.size() == 1);
            CHECK(errors.reported()[0].pointer == pointer);
            continue;
        }
        const bool is_integer = row.type == OptionType::integer;
        for (const double value : outside(row.range, is_integer)) {
            CAPTURE(value);
            const FieldErrors errors = read_row(row, {{row.name, value}}, number, integer, flag);
            REQUIRE(errors.size() == 1);
            const FieldError& error = errors.reported()[0];
            CHECK(error.pointer == pointer);
            CHECK(error.bound == row.range.text());
            if (!is_integer) CHECK(error.unit == std::string(row.unit.code));
        }
        // An end that is closed is allowed, stored in SI; the echo gives the client's number.
        const double end = row.range.max_open ? row.range.min : row.range.max;
        const FieldErrors errors = read_row(row, {{row.name, end}}, number, integer, flag);
        CHECK(errors.empty());
        if (is_integer) {
            CHECK(integer == static_cast<int>(end));
        } else {
            CHECK(number == to_si(end, row.unit));
            json echoed = json::object();
            put_option(echoed, row.id, number);
            CHECK(echoed[std::string(row.name)].get<double>() == end);
        }
        // Not a number at all.
        const FieldErrors wrong = read_row(row, {{row.name, "fast"}}, number, integer, flag);
        REQUIRE(wrong.size() == 1);
        CHECK(wrong.reported()[0].pointer == pointer);
    }
}
