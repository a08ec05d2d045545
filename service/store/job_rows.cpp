// Values of the SQL backends as C++ values and rows of the jobs table as records (job_rows.h).

#include "service/store/job_rows.h"

#include <array>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

namespace rollgap::service::store::detail {

std::string param_text(const Param& param) {
    if (const auto* i = std::get_if<std::int64_t>(&param)) return std::to_string(*i);
    if (const auto* d = std::get_if<double>(&param)) {
        std::array<char, 32> buffer{};
        const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), *d);
        return error == std::errc{} ? std::string(buffer.data(), end) : std::string("0");
    }
    if (const auto* s = std::get_if<std::string>(&param)) return *s;
    return {};
}

std::int64_t to_int(const Value& value) {
    if (!value) return 0;
    std::int64_t number = 0;
    std::from_chars(value->data(), value->data() + value->size(), number);
    return number;
}

namespace {

std::optional<std::int64_t> to_optional_int(const Value& value) {
    if (!value) return std::nullopt;
    return to_int(value);
}

double to_double(const Value& value) { return value ? std::strtod(value->c_str(), nullptr) : 0.0; }

}  // namespace

std::string random_hex() {
    std::random_device source;
    std::string text;
    text.reserve(32);
    for (int i = 0; i < 4; ++i) {
        std::array<char, 9> part{};
        std::snprintf(part.data(), part.size(), "%08x", static_cast<unsigned>(source()));
        text += part.data();
    }
    return text;
}

std::string labels_text(const std::vector<std::pair<std::string, std::string>>& labels) {
    std::string text;
    for (const auto& [name, value] : labels) text += name + "=" + value + "\n";
    return text;
}

std::vector<std::pair<std::string, std::string>> labels_from_text(std::string_view text) {
    std::vector<std::pair<std::string, std::string>> labels;
    while (!text.empty()) {
        const std::size_t end = text.find('\n');
        const std::string_view line = text.substr(0, end);
        text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
        const std::size_t equals = line.find('=');
        if (equals == std::string_view::npos) continue;
        labels.emplace_back(std::string(line.substr(0, equals)),
                            std::string(line.substr(equals + 1)));
    }
    return labels;
}

JobRecord job_from_row(const Row& r) {
    JobRecord job;
    job.id = r.at(0).value_or("");
    job.analysis = r.at(1).value_or("");
    job.request = r.at(2).value_or("");
    job.state = job_state_from_name(r.at(3).value_or("")).value_or(JobState::failed);
    job.result = r.at(5);
    job.problem = r.at(6);
    job.instance = r.at(7).value_or("");
    job.created_ms = to_int(r.at(8));
    job.started_ms = to_optional_int(r.at(9));
    job.finished_ms = to_optional_int(r.at(10));
    job.deadline_ms = to_int(r.at(11));
    job.cancel_requested = to_int(r.at(12)) != 0;
    job.points = to_int(r.at(13));
    job.chunks = to_int(r.at(14));
    job.chunks_done = to_int(r.at(16));
    job.points_done = to_int(r.at(17));
    job.worker = r.at(18);
    if (r.size() > 20) {
        job.labels = labels_from_text(r.at(19).value_or(""));
        job.retention_ms = to_optional_int(r.at(20));
    }
    if (r.size() > 24 && r.at(21)) {
        CallbackStatus callback;
        callback.url = *r.at(21);
        if (r.at(22)) callback.state = *r.at(22);
        callback.attempts = to_int(r.at(23));
        callback.last_error = r.at(24);
        job.callback = std::move(callback);
    }
    if (job.state == JobState::succeeded) {
        job.progress = 1.0;
    } else if (job.points > 0) {
        job.progress = static_cast<double>(job.points_done) / static_cast<double>(job.points);
    } else {
        job.progress = to_double(r.at(4));
    }
    return job;
}

}  // namespace rollgap::service::store::detail
