#include "tools/reproduce_paper/output.h"

namespace rollgap::tools::paper {

bool Csv::write(const fs::path& path) const {
    std::ofstream out(path, std::ios::binary);
    if (!out) return false;
    auto line = [&](const std::vector<std::string>& cells) {
        for (std::size_t i = 0; i < cells.size(); ++i) {
            if (i) out << ',';
            const bool quote = cells[i].find_first_of(",\"\n") != std::string::npos;
            if (quote) {
                out << '"';
                for (char c : cells[i]) out << (c == '"' ? "\"\"" : std::string(1, c));
                out << '"';
            } else {
                out << cells[i];
            }
        }
        out << '\n';
    };
    line(header_);
    for (const auto& r : rows_) line(r);
    return static_cast<bool>(out);
}

void Output::csv(const std::string& name, const Csv& table) {
    const fs::path path = dir / name;
    if (!table.write(path)) {
        log("cannot write " + path.string());
        ok = false;
    }
    files.push_back(name);
}

void Output::svg(const std::string& name, const Plot& plot) {
    const fs::path path = dir / name;
    if (!tools::write_svg(path, plot)) {
        log("cannot write " + path.string());
        ok = false;
    }
    files.push_back(name);
}

std::string Output::image(const std::string& name, const std::string& alt) const {
    return "![" + alt + "](" + link + "/" + name + ")";
}

}  // namespace rollgap::tools::paper
