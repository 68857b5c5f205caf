#include "quadcage/bench/inputs.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>

#include "quadcage/core/errors.h"

namespace quadcage::bench {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string safe_dir_name(const std::string& name) {
    std::string s;
    for (char c : name) {
        const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
        s += ok ? c : '_';
    }
    if (s.empty() || s == "." || s == "..") s = "mesh";
    return s;
}

struct Expander {
    std::vector<std::string> files;
    std::set<std::string> seen;       // canonical paths of meshes taken
    std::vector<std::string> stack;   // manifests being read (to detect a cycle)

    void add_file(const fs::path& p) {
        std::error_code ec;
        const fs::path canon = fs::weakly_canonical(p, ec);
        const std::string key = ec ? p.string() : canon.string();
        if (seen.insert(key).second) files.push_back(p.string());
    }

    void add_folder(const fs::path& dir, const std::string& where) {
        std::vector<fs::path> found;
        std::error_code ec;
        for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
            std::error_code ec2;
            if (it->is_regular_file(ec2) && is_mesh_file_name(it->path().filename().string()))
                found.push_back(it->path());
        }
        if (ec) throw InvalidInput(where + ": cannot list the folder (" + ec.message() + ")");
        if (found.empty()) throw InvalidInput(where + ": the folder holds no .obj, .ply, .off or .stl file");
        std::sort(found.begin(), found.end(),
                  [](const fs::path& a, const fs::path& b) { return a.filename().string() < b.filename().string(); });
        for (const fs::path& f : found) add_file(f);
    }

    void add_manifest(const fs::path& file, const std::string& where) {
        std::error_code ec;
        const std::string key = fs::weakly_canonical(file, ec).string();
        if (std::find(stack.begin(), stack.end(), key) != stack.end())
            throw InvalidInput(where + ": the manifest includes itself");
        std::ifstream in(file);
        if (!in) throw InvalidInput(where + ": cannot read the manifest");
        stack.push_back(key);
        const size_t before = files.size();
        std::string line;
        int number = 0;
        while (std::getline(in, line)) {
            ++number;
            if (!line.empty() && line.back() == '\r') line.pop_back();
            const size_t a = line.find_first_not_of(" \t");
            if (a == std::string::npos || line[a] == '#') continue;
            const size_t b = line.find_last_not_of(" \t");
            fs::path p(line.substr(a, b - a + 1));
            if (p.is_relative()) p = file.parent_path() / p;
            add(p, file.string() + ":" + std::to_string(number) + ": " + p.string());
        }
        stack.pop_back();
        if (files.size() == before) throw InvalidInput(where + ": the manifest lists no mesh");
    }

    void add(const fs::path& p, const std::string& where) {
        std::error_code ec;
        const fs::file_status st = fs::status(p, ec);
        if (ec || !fs::exists(st)) throw InvalidInput(where + ": no such file or folder");
        if (fs::is_directory(st)) add_folder(p, where);
        else if (lower(p.extension().string()) == ".txt") add_manifest(p, where);
        else add_file(p);
    }
};

}  // namespace

bool is_mesh_file_name(const std::string& path) {
    const std::string ext = lower(fs::path(path).extension().string());
    return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl";
}

std::vector<BenchInput> expand_inputs(const std::vector<std::string>& paths) {
    if (paths.empty()) throw InvalidInput("no PATH given: name meshes, folders of meshes or manifests (.txt)");
    Expander e;
    for (const std::string& p : paths) e.add(p, p);
    std::vector<BenchInput> out;
    std::set<std::string> names, dirs;
    for (const std::string& f : e.files) {
        const std::string stem = fs::path(f).stem().string();
        std::string name = stem.empty() ? "mesh" : stem;
        for (int k = 2; names.count(name) || dirs.count(safe_dir_name(name)); ++k)
            name = stem + "_" + std::to_string(k);
        names.insert(name);
        dirs.insert(safe_dir_name(name));
        out.push_back({f, name, safe_dir_name(name)});
    }
    return out;
}

}  // namespace quadcage::bench
