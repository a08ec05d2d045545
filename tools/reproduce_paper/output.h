#pragma once
// Where the reproduction writes: CSV tables and SVG plots into the output folder, remembered
// for the report's file list, and image links relative to the report.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tools/reproduce_paper/common.h"

namespace rollgap::tools::paper {

namespace fs = std::filesystem;

class Csv {
public:
    explicit Csv(std::vector<std::string> header) : header_(std::move(header)) {}
    void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
    bool write(const fs::path& path) const;

private:
    std::vector<std::string> header_;
    std::vector<std::vector<std::string>> rows_;
};

struct Output {
    fs::path dir;      // CSV and SVG files
    fs::path doc;      // the markdown
    std::string link;  // dir relative to the markdown's folder, for image links
    std::vector<std::string> files;
    bool ok = true;

    void csv(const std::string& name, const Csv& table);
    void svg(const std::string& name, const Plot& plot);
    std::string image(const std::string& name, const std::string& alt) const;
};

}  // namespace rollgap::tools::paper
