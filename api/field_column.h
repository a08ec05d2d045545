#pragma once
// A column of a field table written by path: the typical ranges and the names of the scenario
// and tandem field tables are lists of (path, value) beside the rows, so that each row's
// constructor call stays readable. A path that names no row is a programming error (thrown at
// start-up, when the table is built).

#include <algorithm>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rollgap::api {

// `column`: (path, value) pairs, each value converted to the member's type.
template <class Row, class Column, class Member>
void set_column(std::vector<Row>& rows, const Column& column, Member Row::*member,
                std::string_view what) {
    for (const auto& [path, value] : column) {
        const auto row = std::find_if(rows.begin(), rows.end(),
                                      [path = path](const Row& r) { return r.path == path; });
        if (row == rows.end())
            throw std::logic_error(std::string(what) + " of no field: " + std::string(path));
        (*row).*member = Member(value);
    }
}

}  // namespace rollgap::api
