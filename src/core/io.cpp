#include "quadcage/core/io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "quadcage/core/errors.h"

namespace quadcage {
namespace {

// ------------------------------------------------------------------------------------------------
// Common helpers

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw InvalidInput(path + ": " + what);
}

[[noreturn]] void fail_at(const std::string& path, int line, const std::string& what) {
    throw InvalidInput(path + ", line " + std::to_string(line) + ": " + what);
}

// Long garbage tokens (e.g. binary bytes read as text) would make messages unreadable.
std::string quote(std::string_view token) {
    std::string out = "'";
    const size_t limit = 40;
    for (size_t i = 0; i < token.size() && i < limit; ++i) {
        const unsigned char ch = static_cast<unsigned char>(token[i]);
        out += std::isprint(ch) ? static_cast<char>(ch) : '?';
    }
    if (token.size() > limit) out += "...";
    return out + "'";
}

// A number for a message (%g).
std::string short_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// The parsers work on the whole file in memory: it is simpler and much faster than streams.
// Only regular files are read: a directory cannot be parsed, a device such as /dev/zero never ends
// and a FIFO may block forever. Checked on the path (following symbolic links) before opening it.
void require_regular_file(const std::string& path) {
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(st)) {
        if (ec && ec != std::errc::no_such_file_or_directory)
            fail(path, "cannot open file (" + ec.message() + ")");
        fail(path, "cannot open file (No such file or directory)");
    }
    using std::filesystem::file_type;
    switch (st.type()) {
        case file_type::regular: return;
        case file_type::directory: fail(path, "is a directory, not a mesh file");
        case file_type::fifo: fail(path, "is a FIFO (named pipe), not a regular file; save the mesh to a file first");
        case file_type::socket: fail(path, "is a socket, not a regular file; save the mesh to a file first");
        case file_type::character:
        case file_type::block: fail(path, "is a device, not a regular file; give a mesh file");
        default: fail(path, "is not a regular file; give a mesh file");
    }
}

std::string read_whole_file(const std::string& path) {
    require_regular_file(path);
    std::error_code ec;
    FilePtr file(std::fopen(path.c_str(), "rb"));
    if (!file) fail(path, std::string("cannot open file (") + std::strerror(errno) + ")");
    std::string data;
    const auto size = std::filesystem::file_size(path, ec);
    if (!ec) data.reserve(static_cast<size_t>(size));
    char chunk[1 << 16];
    for (;;) {
        const size_t n = std::fread(chunk, 1, sizeof chunk, file.get());
        data.append(chunk, n);
        if (n < sizeof chunk) break;
    }
    if (std::ferror(file.get())) fail(path, std::string("error while reading (") + std::strerror(errno) + ")");
    return data;
}

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return ext;
}

// std::from_chars rejects a leading '+', which some exporters write.
bool parse_double(std::string_view tok, double& out) {
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (b != e && *b == '+') ++b;
    if (b == e) return false;
    const auto r = std::from_chars(b, e, out);
    return r.ec == std::errc() && r.ptr == e;
}

bool parse_int(std::string_view tok, long long& out) {
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (b != e && *b == '+') ++b;
    if (b == e) return false;
    const auto r = std::from_chars(b, e, out);
    return r.ec == std::errc() && r.ptr == e;
}

// Indices are stored as written, even when out of range (validate() reports them); only values
// that do not fit an int at all are clamped, to a value that is still out of range.
int to_index(long long v) {
    if (v > INT_MAX) return INT_MAX;
    if (v < INT_MIN) return INT_MIN;
    return static_cast<int>(v);
}

// What a reader found, and (for read_polygon_mesh()) where to record each kept face's corner count.
struct ReadInfo : LoadInfo {
    std::vector<int>* polygon_sizes = nullptr;
};

// Fan triangulation of one polygon as read; counts what was split or dropped. The fan (c0, ck,
// ck+1) and the corner count give the polygon back (read_polygon_mesh()).
void add_polygon(const std::vector<int>& corners, Mesh& mesh, ReadInfo& info) {
    if (corners.size() < 3) {
        ++info.dropped_faces;
        return;
    }
    if (corners.size() > 3) ++info.polygons_split;
    if (info.polygon_sizes) info.polygon_sizes->push_back(static_cast<int>(corners.size()));
    for (size_t k = 1; k + 1 < corners.size(); ++k)
        mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
}

// A cursor over text that knows its line number (for error messages).
class TextCursor {
public:
    TextCursor(const char* begin, const char* end, int line = 1) : p_(begin), end_(end), line_(line) {}

    bool at_end() const { return p_ == end_; }
    int line() const { return line_; }
    const char* pos() const { return p_; }

    /// Skips blanks within the current line (not the newline).
    void skip_blanks() {
        while (p_ != end_ && is_blank(*p_)) ++p_;
    }

    /// After skip_blanks(): nothing more on this line.
    bool at_line_end() const { return p_ == end_ || *p_ == '\n'; }

    /// Moves past the next newline.
    void skip_line() {
        const void* nl = std::memchr(p_, '\n', static_cast<size_t>(end_ - p_));
        if (!nl) {
            p_ = end_;
            return;
        }
        p_ = static_cast<const char*>(nl) + 1;
        ++line_;
    }

    /// Skips whitespace including newlines, and '#' comments if `comments`. False at the end.
    bool skip_space(bool comments) {
        while (p_ != end_) {
            const char ch = *p_;
            if (ch == '\n') {
                ++line_;
                ++p_;
            } else if (is_blank(ch)) {
                ++p_;
            } else if (comments && ch == '#') {
                skip_line();
            } else {
                return true;
            }
        }
        return false;
    }

    /// The run of non-whitespace characters at the cursor (empty at a line end).
    std::string_view token() {
        const char* b = p_;
        while (p_ != end_ && !is_blank(*p_) && *p_ != '\n') ++p_;
        return {b, static_cast<size_t>(p_ - b)};
    }

    /// The next token on the current line; empty if the line ends (or a '#' comment starts).
    std::string_view token_in_line() {
        skip_blanks();
        if (p_ != end_ && *p_ == '#') return {};
        return token();
    }

private:
    static bool is_blank(char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\v' || ch == '\f'; }

    const char* p_;
    const char* end_;
    int line_;
};

// ------------------------------------------------------------------------------------------------
// OBJ

// An OBJ face corner that names a vertex not (yet) defined: positive indices may refer forward,
// so whether it exists is known only at the end of the file.
struct ObjForwardIndex {
    long long index;  // 1-based, as written
    int line;
};

[[noreturn]] void fail_obj_index(const std::string& path, int line, long long written, long long defined, bool at_end) {
    fail_at(path, line, "face corner " + std::to_string(written) + " refers to a vertex that does not exist (the file " +
                            (at_end ? "defines " : "has defined ") + std::to_string(defined) + " vertices" +
                            (at_end ? "" : " so far") +
                            "; OBJ indices count from 1, negative ones back from the last vertex defined)");
}

void read_obj(const std::string& path, std::string_view text, Mesh& mesh, ReadInfo& info) {
    TextCursor c(text.data(), text.data() + text.size());
    std::vector<int> corners;
    std::vector<ObjForwardIndex> forward;  // corners beyond the vertices defined so far
    while (!c.at_end()) {
        const std::string_view key = c.token_in_line();
        if (key == "v") {
            double xyz[3];
            for (int k = 0; k < 3; ++k) {
                const std::string_view tok = c.token_in_line();
                if (tok.empty())
                    fail_at(path, c.line(), "vertex has " + std::to_string(k) + " coordinates, expected 3 ('v x y z')");
                if (!parse_double(tok, xyz[k]))
                    fail_at(path, c.line(), "malformed number " + quote(tok) + " in vertex coordinates");
            }
            mesh.points.push_back({xyz[0], xyz[1], xyz[2]});
        } else if (key == "f") {
            corners.clear();
            const long long defined = static_cast<long long>(mesh.points.size());
            for (std::string_view tok = c.token_in_line(); !tok.empty(); tok = c.token_in_line()) {
                // Only the position index matters; the vt/vn parts are checked but unused.
                const size_t slash = tok.find('/');
                long long v = 0;
                bool ok = parse_int(tok.substr(0, slash), v);
                for (size_t at = slash; ok && at != std::string_view::npos;) {
                    const size_t next = tok.find('/', at + 1);
                    const std::string_view part = tok.substr(at + 1, next == std::string_view::npos ? next : next - at - 1);
                    long long unused = 0;
                    ok = part.empty() || parse_int(part, unused);
                    at = next;
                }
                if (!ok) fail_at(path, c.line(), "malformed face corner " + quote(tok) + " (expected v, v/vt, v//vn or v/vt/vn)");
                // Positive indices are 1-based; negative ones count back from the last vertex so far.
                // Errors are reported in the file's own numbering (as written), not 0-based.
                if (v == 0) fail_at(path, c.line(), "face corner 0 is not a vertex index (OBJ indices count from 1, negative ones back from the last vertex defined)");
                if (v < 0 && defined + v < 0) fail_obj_index(path, c.line(), v, defined, false);
                if (v > defined) forward.push_back({v, c.line()});
                corners.push_back(to_index(v < 0 ? defined + v : v - 1));
            }
            add_polygon(corners, mesh, info);
        }
        // Everything else (vt, vn, vp, g, o, s, usemtl, mtllib, l, comments, ...) is not geometry we use.
        c.skip_line();
    }
    const long long total = static_cast<long long>(mesh.points.size());
    for (const ObjForwardIndex& f : forward)
        if (f.index > total) fail_obj_index(path, f.line, f.index, total, true);
}

// ------------------------------------------------------------------------------------------------
// OFF

bool is_off_keyword(std::string_view tok) {
    if (tok.size() < 3 || tok.substr(tok.size() - 3) != "OFF") return false;
    for (char ch : tok.substr(0, tok.size() - 3))
        if (!std::strchr("STCN4n", ch)) return false;
    return true;
}

void read_off(const std::string& path, std::string_view text, Mesh& mesh, ReadInfo& info) {
    const char* const end = text.data() + text.size();
    TextCursor c(text.data(), end);
    c.skip_space(true);
    TextCursor after_header = c;
    const std::string_view header = after_header.token();
    if (is_off_keyword(header)) {
        if (header.find('4') != std::string_view::npos || header.find('n') != std::string_view::npos)
            fail_at(path, c.line(), "OFF variant " + quote(header) + " (not 3-dimensional) is not supported");
        TextCursor peek = after_header;
        if (peek.token_in_line() == "BINARY")
            fail_at(path, c.line(), "binary OFF is not supported; convert it to ASCII OFF, PLY or OBJ");
        c = after_header;
    }
    // Otherwise (only for '.off' files) the header is missing and the counts come first.

    long long counts[2];
    const char* count_names[2] = {"vertex count", "face count"};
    for (int k = 0; k < 2; ++k) {
        if (!c.skip_space(true)) fail(path, "truncated OFF header: missing the " + std::string(count_names[k]));
        const std::string_view tok = c.token();
        if (!parse_int(tok, counts[k]) || counts[k] < 0)
            fail_at(path, c.line(), "malformed " + std::string(count_names[k]) + " " + quote(tok) + " in OFF header");
    }
    c.skip_line();  // the edge count (unused) and anything else on that line
    const long long num_v = counts[0];
    const long long num_f = counts[1];

    // Counts come from the file: reserve no more than the bytes left could hold.
    const long long room = static_cast<long long>(end - c.pos()) / 2 + 1;
    mesh.points.reserve(static_cast<size_t>(std::min(num_v, room)));
    mesh.triangles.reserve(static_cast<size_t>(std::min(num_f, room)));

    for (long long i = 0; i < num_v; ++i) {
        if (!c.skip_space(true))
            fail(path, "truncated OFF: expected " + std::to_string(num_v) + " vertices, file ends after " + std::to_string(i));
        double xyz[3];
        for (int k = 0; k < 3; ++k) {
            const std::string_view tok = c.token_in_line();
            if (tok.empty())
                fail_at(path, c.line(), "vertex " + std::to_string(i) + " has " + std::to_string(k) + " coordinates, expected 3");
            if (!parse_double(tok, xyz[k]))
                fail_at(path, c.line(), "malformed number " + quote(tok) + " in vertex " + std::to_string(i));
        }
        mesh.points.push_back({xyz[0], xyz[1], xyz[2]});
        c.skip_line();  // colours, normals, texture coordinates
    }

    std::vector<int> corners;
    for (long long i = 0; i < num_f; ++i) {
        if (!c.skip_space(true))
            fail(path, "truncated OFF: expected " + std::to_string(num_f) + " faces, file ends after " + std::to_string(i));
        const std::string_view count_tok = c.token();
        long long n = 0;
        if (!parse_int(count_tok, n) || n < 0)
            fail_at(path, c.line(), "malformed corner count " + quote(count_tok) + " in face " + std::to_string(i));
        corners.clear();
        for (long long k = 0; k < n; ++k) {
            const std::string_view tok = c.token_in_line();
            long long v = 0;
            if (tok.empty())
                fail_at(path, c.line(), "face " + std::to_string(i) + " lists only " + std::to_string(k) + " of its " +
                                            std::to_string(n) + " vertex indices");
            if (!parse_int(tok, v))
                fail_at(path, c.line(), "malformed vertex index " + quote(tok) + " in face " + std::to_string(i));
            corners.push_back(to_index(v));
        }
        add_polygon(corners, mesh, info);
        c.skip_line();  // face colour
    }
}

// ------------------------------------------------------------------------------------------------
// STL

// Welds corners with bit-identical coordinates (STL stores every triangle's corners separately).
class Welder {
public:
    explicit Welder(Mesh& mesh, size_t expected_corners) : mesh_(mesh) { map_.reserve(expected_corners / 4 + 16); }

    int add(const Vec3& p) {
        Key key{bits(p.x), bits(p.y), bits(p.z)};
        const auto [it, inserted] = map_.try_emplace(key, static_cast<int>(mesh_.points.size()));
        if (inserted) mesh_.points.push_back(p);
        return it->second;
    }

private:
    struct Key {
        std::uint64_t a, b, c;
        bool operator==(const Key& o) const { return a == o.a && b == o.b && c == o.c; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            std::uint64_t h = k.a * 0x9E3779B97F4A7C15ull;
            h ^= (k.b + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2)) * 0xBF58476D1CE4E5B9ull;
            h ^= (k.c + 0x85EBCA77C2B2AE63ull + (h << 6) + (h >> 2)) * 0x94D049BB133111EBull;
            return static_cast<size_t>(h ^ (h >> 31));
        }
    };
    // -0 and +0 are the same position: exporters are not consistent about the sign of zero.
    static std::uint64_t bits(double v) {
        if (v == 0) v = 0;
        std::uint64_t b;
        std::memcpy(&b, &v, sizeof b);
        return b;
    }

    Mesh& mesh_;
    std::unordered_map<Key, int, KeyHash> map_;
};

bool host_is_little_endian() {
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    return first == 1;
}

template <class T>
T load_scalar(const char* p, bool swap) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, p, sizeof(T));
    if (swap) std::reverse(bytes, bytes + sizeof(T));
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    return v;
}

std::uint32_t stl_binary_count(std::string_view data) {
    return load_scalar<std::uint32_t>(data.data() + 80, !host_is_little_endian());
}

bool is_binary_stl_size(std::string_view data) {
    return data.size() >= 84 && data.size() == 84 + 50 * static_cast<std::uint64_t>(stl_binary_count(data));
}

void read_stl_binary(const std::string& path, std::string_view data, Mesh& mesh, ReadInfo& info) {
    if (data.size() < 84) fail(path, "truncated binary STL: " + std::to_string(data.size()) + " bytes, the header alone is 84");
    const std::uint64_t n = stl_binary_count(data);
    if (!is_binary_stl_size(data))
        fail(path, "truncated or corrupt binary STL: header says " + std::to_string(n) + " triangles (" +
                       std::to_string(84 + 50 * n) + " bytes), file has " + std::to_string(data.size()) + " bytes");
    const bool swap = !host_is_little_endian();
    Welder welder(mesh, 3 * n);
    mesh.triangles.reserve(n);
    for (std::uint64_t t = 0; t < n; ++t) {
        const char* rec = data.data() + 84 + 50 * t + 12;  // skip the normal: we use the winding
        Triangle tri;
        for (int k = 0; k < 3; ++k) {
            const char* q = rec + 12 * k;
            tri[k] = welder.add({load_scalar<float>(q, swap), load_scalar<float>(q + 4, swap), load_scalar<float>(q + 8, swap)});
        }
        mesh.triangles.push_back(tri);
    }
    if (info.polygon_sizes) info.polygon_sizes->insert(info.polygon_sizes->end(), n, 3);
    info.welded_vertices = static_cast<int>(3 * n - mesh.points.size());
}

void read_stl_ascii(const std::string& path, std::string_view text, Mesh& mesh, ReadInfo& info) {
    TextCursor c(text.data(), text.data() + text.size());
    Welder welder(mesh, text.size() / 40);
    std::vector<int> corners;
    long long num_corners = 0;
    int facet_line = 0;
    while (c.skip_space(false)) {
        const std::string_view tok = c.token();
        if (tok == "vertex") {
            double xyz[3];
            for (int k = 0; k < 3; ++k) {
                const std::string_view num = c.token_in_line();
                if (num.empty()) fail_at(path, c.line(), "'vertex' has " + std::to_string(k) + " coordinates, expected 3");
                if (!parse_double(num, xyz[k])) fail_at(path, c.line(), "malformed number " + quote(num) + " in 'vertex'");
            }
            if (corners.empty()) facet_line = c.line();
            corners.push_back(welder.add({xyz[0], xyz[1], xyz[2]}));
            ++num_corners;
        } else if (tok == "endloop") {
            add_polygon(corners, mesh, info);
            corners.clear();
        } else if (tok == "solid" || tok == "endsolid" || tok == "facet") {
            c.skip_line();  // solid names and facet normals (we use the winding)
        } else if (tok != "outer" && tok != "loop" && tok != "endfacet") {
            fail_at(path, c.line(), "unexpected " + quote(tok) + " in ASCII STL (expected facet/outer loop/vertex/endloop/endfacet)");
        }
    }
    if (!corners.empty()) fail_at(path, facet_line, "truncated ASCII STL: file ends inside the loop that starts here (no 'endloop')");
    info.welded_vertices = static_cast<int>(num_corners - static_cast<long long>(mesh.points.size()));
}

// ------------------------------------------------------------------------------------------------
// PLY

enum class PlyType : std::uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };

int size_of(PlyType t) {
    switch (t) {
        case PlyType::i8: case PlyType::u8: return 1;
        case PlyType::i16: case PlyType::u16: return 2;
        case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
        case PlyType::f64: return 8;
    }
    return 0;
}

bool parse_ply_type(std::string_view name, PlyType& t) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::i8},     {"int8", PlyType::i8},     {"uchar", PlyType::u8},   {"uint8", PlyType::u8},
        {"short", PlyType::i16},   {"int16", PlyType::i16},   {"ushort", PlyType::u16}, {"uint16", PlyType::u16},
        {"int", PlyType::i32},     {"int32", PlyType::i32},   {"uint", PlyType::u32},   {"uint32", PlyType::u32},
        {"float", PlyType::f32},   {"float32", PlyType::f32}, {"double", PlyType::f64}, {"float64", PlyType::f64},
    };
    for (const auto& [n, type] : names)
        if (name == n) {
            t = type;
            return true;
        }
    return false;
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::f32;
    bool is_list = false;
    PlyType count_type = PlyType::u8;
};

struct PlyElement {
    std::string name;
    long long count = 0;
    std::vector<PlyProperty> props;
};

enum class PlyEncoding { ascii, binary_le, binary_be };

struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::ascii;
    std::vector<PlyElement> elements;
    size_t data_offset = 0;  // first byte after "end_header\n"
    int data_line = 0;       // line number of that byte (ascii)
};

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        const size_t b = i;
        while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i > b) words.push_back(line.substr(b, i - b));
    }
    return words;
}

PlyHeader parse_ply_header(const std::string& path, std::string_view data) {
    PlyHeader h;
    bool have_format = false;
    size_t pos = 0;
    for (int line = 1;; ++line) {
        if (pos >= data.size()) fail(path, "truncated PLY header: no 'end_header' line");
        size_t nl = data.find('\n', pos);
        const bool last = nl == std::string_view::npos;
        if (last) nl = data.size();
        const std::string_view text = data.substr(pos, nl - pos);
        pos = nl + 1;
        const std::vector<std::string_view> w = split_words(text);
        // A header line cut off by the end of the file would otherwise parse as a malformed one.
        if (last && !(w.size() == 1 && w[0] == "end_header"))
            fail_at(path, line, "truncated PLY header: the file ends before 'end_header'");
        if (w.empty()) continue;
        if (line == 1) {
            if (w[0] != "ply") fail(path, "not a PLY file (the first line is not 'ply')");
            continue;
        }
        if (w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "end_header") {
            h.data_offset = std::min(pos, data.size());
            h.data_line = line + 1;
            break;
        }
        if (w[0] == "format") {
            if (w.size() < 2) fail_at(path, line, "PLY 'format' line has no format");
            if (w[1] == "ascii") h.encoding = PlyEncoding::ascii;
            else if (w[1] == "binary_little_endian") h.encoding = PlyEncoding::binary_le;
            else if (w[1] == "binary_big_endian") h.encoding = PlyEncoding::binary_be;
            else fail_at(path, line, "unknown PLY format " + quote(w[1]) + " (expected ascii, binary_little_endian or binary_big_endian)");
            have_format = true;
        } else if (w[0] == "element") {
            PlyElement el;
            if (w.size() < 3 || !parse_int(w[2], el.count) || el.count < 0)
                fail_at(path, line, "malformed PLY element line (expected 'element <name> <count>')");
            el.name = std::string(w[1]);
            h.elements.push_back(std::move(el));
        } else if (w[0] == "property") {
            if (h.elements.empty()) fail_at(path, line, "PLY property before any element");
            PlyProperty prop;
            if (w.size() >= 2 && w[1] == "list") {
                if (w.size() < 5 || !parse_ply_type(w[2], prop.count_type) || !parse_ply_type(w[3], prop.type))
                    fail_at(path, line, "malformed PLY list property (expected 'property list <count type> <type> <name>')");
                if (prop.count_type == PlyType::f32 || prop.count_type == PlyType::f64)
                    fail_at(path, line, "PLY list count type must be an integer type, not " + quote(w[2]));
                prop.is_list = true;
                prop.name = std::string(w[4]);
            } else {
                if (w.size() < 3 || !parse_ply_type(w[1], prop.type))
                    fail_at(path, line, "malformed PLY property (expected 'property <type> <name>' with a PLY scalar type)");
                prop.name = std::string(w[2]);
            }
            h.elements.back().props.push_back(std::move(prop));
        } else {
            fail_at(path, line, "unknown PLY header keyword " + quote(w[0]));
        }
    }
    if (!have_format) fail(path, "PLY header has no 'format' line");
    return h;
}

// Reads scalars of a binary PLY body. Returns false when the data ends (the caller reports
// truncation with the element it was reading).
class PlyBinaryReader {
public:
    PlyBinaryReader(std::string_view data, size_t offset, bool big_endian)
        : p_(data.data() + offset), end_(data.data() + data.size()), swap_(big_endian == host_is_little_endian()) {}

    bool number(PlyType t, double& out) {
        const int n = size_of(t);
        if (end_ - p_ < n) return false;
        switch (t) {
            case PlyType::i8: out = load_scalar<std::int8_t>(p_, false); break;
            case PlyType::u8: out = load_scalar<std::uint8_t>(p_, false); break;
            case PlyType::i16: out = load_scalar<std::int16_t>(p_, swap_); break;
            case PlyType::u16: out = load_scalar<std::uint16_t>(p_, swap_); break;
            case PlyType::i32: out = load_scalar<std::int32_t>(p_, swap_); break;
            case PlyType::u32: out = load_scalar<std::uint32_t>(p_, swap_); break;
            case PlyType::f32: out = load_scalar<float>(p_, swap_); break;
            case PlyType::f64: out = load_scalar<double>(p_, swap_); break;
        }
        p_ += n;
        return true;
    }

    bool integer(PlyType t, long long& out) {
        const int n = size_of(t);
        if (end_ - p_ < n) return false;
        switch (t) {
            case PlyType::i8: out = load_scalar<std::int8_t>(p_, false); break;
            case PlyType::u8: out = load_scalar<std::uint8_t>(p_, false); break;
            case PlyType::i16: out = load_scalar<std::int16_t>(p_, swap_); break;
            case PlyType::u16: out = load_scalar<std::uint16_t>(p_, swap_); break;
            case PlyType::i32: out = load_scalar<std::int32_t>(p_, swap_); break;
            // An index written as uint 0xFFFFFFFF means -1 (the strip restart, or "no vertex").
            case PlyType::u32: out = load_scalar<std::int32_t>(p_, swap_); break;
            case PlyType::f32: out = float_to_integer(load_scalar<float>(p_, swap_)); break;
            case PlyType::f64: out = float_to_integer(load_scalar<double>(p_, swap_)); break;
        }
        p_ += n;
        return true;
    }

    bool skip(PlyType t, long long count = 1) {
        // count comes from the file: compare without multiplying (no overflow).
        if (count < 0 || count > (end_ - p_) / size_of(t)) return false;
        p_ += size_of(t) * count;
        return true;
    }

    long long bytes_left() const { return end_ - p_; }

    /// Most items of `min_bytes` bytes each (>= 1) that the rest of the file can hold.
    long long max_items(long long min_bytes, size_t) const { return bytes_left() / std::max(1ll, min_bytes); }
    void at(const std::string&, long long) {}  // binary errors are all truncation, reported by the caller

private:
    static long long float_to_integer(double v) {
        // Out of any int's range: keep it out of range rather than wrap around.
        if (!(v >= -9.0e18 && v <= 9.0e18)) return LLONG_MAX;
        return static_cast<long long>(v);
    }

    const char* p_;
    const char* end_;
    bool swap_;
};


class PlyAsciiReader {
public:
    PlyAsciiReader(const std::string& path, std::string_view data, size_t offset, int line)
        : path_(path), c_(data.data() + offset, data.data() + data.size(), line), end_(data.data() + data.size()) {}

    bool number(PlyType, double& out) {
        if (!c_.skip_space(false)) return false;
        const std::string_view tok = c_.token();
        if (!parse_double(tok, out)) malformed("number", tok);
        return true;
    }

    bool integer(PlyType t, long long& out) {
        if (!c_.skip_space(false)) return false;
        const std::string_view tok = c_.token();
        if (parse_int(tok, out)) {
            // As in binary files: a uint index of 4294967295 is -1 (the strip restart).
            if (t == PlyType::u32 && out == 0xFFFFFFFFll) out = -1;
            return true;
        }
        double v = 0;
        if ((t == PlyType::f32 || t == PlyType::f64) && parse_double(tok, v) && v >= -9.0e18 && v <= 9.0e18) {
            out = static_cast<long long>(v);
            return true;
        }
        malformed("integer", tok);
    }

    bool skip(PlyType, long long count = 1) {
        for (long long i = 0; i < count; ++i) {
            if (!c_.skip_space(false)) return false;
            const std::string_view tok = c_.token();
            double unused = 0;
            if (!parse_double(tok, unused)) malformed("number", tok);
        }
        return true;
    }

    long long bytes_left() const { return end_ - c_.pos(); }

    /// Most items of `tokens` tokens each (>= 1) that the rest of the file can hold: n tokens take at
    /// least 2n - 1 bytes (one character each, separated by whitespace).
    long long max_items(long long, size_t tokens) const {
        return (bytes_left() + 1) / 2 / static_cast<long long>(std::max<size_t>(1, tokens));
    }

    void at(const std::string& element, long long index) {
        element_ = &element;
        index_ = index;
    }

private:
    [[noreturn]] void malformed(const char* what, std::string_view tok) const {
        fail_at(path_, c_.line(), std::string("malformed ") + what + " " + quote(tok) + " in PLY element '" +
                                      (element_ ? *element_ : std::string()) + "' " + std::to_string(index_));
    }

    const std::string& path_;
    TextCursor c_;
    const char* end_;
    const std::string* element_ = nullptr;
    long long index_ = 0;
};

enum class PlyRole { vertex, face, tristrips, other };

// Which properties of an element carry the geometry we read.
struct PlyLayout {
    PlyRole role = PlyRole::other;
    int x = -1, y = -1, z = -1;
    int connectivity = -1;  // the vertex_indices list of faces or strips
    long long min_bytes = 0;  // smallest binary size of one item (for sane reserve())
};

PlyLayout layout_of(const std::string& path, const PlyElement& el) {
    PlyLayout lay;
    for (size_t j = 0; j < el.props.size(); ++j) {
        const PlyProperty& prop = el.props[j];
        lay.min_bytes += size_of(prop.is_list ? prop.count_type : prop.type);
        const int idx = static_cast<int>(j);
        if (!prop.is_list) {
            if (prop.name == "x") lay.x = idx;
            else if (prop.name == "y") lay.y = idx;
            else if (prop.name == "z") lay.z = idx;
        } else if (prop.name == "vertex_indices" || (prop.name == "vertex_index" && lay.connectivity < 0)) {
            lay.connectivity = idx;
        }
    }
    if (el.name == "vertex") {
        lay.role = PlyRole::vertex;
        if (lay.x < 0 || lay.y < 0 || lay.z < 0)
            fail(path, "PLY element 'vertex' lacks one of the scalar properties x, y, z");
    } else if (el.name == "face" || el.name == "tristrips") {
        lay.role = el.name == "face" ? PlyRole::face : PlyRole::tristrips;
        if (lay.connectivity < 0)
            fail(path, "PLY element '" + el.name + "' has no list property 'vertex_indices' (or 'vertex_index')");
    }
    return lay;
}

// Triangle k of a strip is (v[k], v[k+1], v[k+2]) with every other triangle flipped, so that all
// have the strip's orientation; -1 restarts a strip. Triangles with a repeated corner only join
// strips (they have no area) and are skipped.
void add_strips(const std::vector<int>& v, Mesh& mesh, ReadInfo& info) {
    size_t start = 0;
    while (start < v.size()) {
        size_t stop = start;
        while (stop < v.size() && v[stop] != -1) ++stop;
        for (size_t k = start; k + 2 < stop; ++k) {
            int a = v[k], b = v[k + 1];
            const int c = v[k + 2];
            if ((k - start) % 2 == 1) std::swap(a, b);
            if (a == b || b == c || a == c) continue;
            mesh.triangles.push_back({a, b, c});
            if (info.polygon_sizes) info.polygon_sizes->push_back(3);
        }
        start = stop + 1;
    }
}

template <class Reader>
void read_ply_body(const std::string& path, const PlyHeader& h, const char* encoding, Reader& r, Mesh& mesh,
                   ReadInfo& info, PlyExtras* extras) {
    std::vector<int> corners;
    for (const PlyElement& el : h.elements) {
        const PlyLayout lay = layout_of(path, el);
        // The optional scalar property of this element that the caller asked for (-1: none).
        int extra = -1;
        if (extras && (lay.role == PlyRole::vertex || lay.role == PlyRole::face)) {
            const std::string& want = lay.role == PlyRole::vertex ? extras->vertex_float_name : extras->face_int_name;
            for (size_t j = 0; j < el.props.size() && !want.empty(); ++j)
                if (!el.props[j].is_list && el.props[j].name == want) extra = static_cast<int>(j);
        }
        auto truncated = [&](long long done) {
            fail(path, std::string("truncated ") + encoding + " PLY: expected " + std::to_string(el.count) + " '" + el.name +
                           "' elements, file ends after " + std::to_string(done));
        };
        // An element without properties takes no bytes: nothing to read, whatever its count (a loop
        // over a count of 2^63 - 1 would never end).
        if (el.props.empty()) continue;
        // The count comes from the file: every item takes at least one byte per property (binary) or
        // one token per property (ASCII), so a count the rest of the file cannot hold is rejected
        // before the loop, and no more than that is reserved.
        const long long most = r.max_items(lay.min_bytes, el.props.size());
        if (el.count > most)
            fail(path, std::string("truncated ") + encoding + " PLY: expected " + std::to_string(el.count) + " '" +
                           el.name + "' elements, but the " + std::to_string(r.bytes_left()) +
                           " bytes left in the file can hold at most " + std::to_string(most) +
                           " (the file is cut short or the header's count is wrong)");
        const long long plausible = el.count;
        if (lay.role == PlyRole::vertex) mesh.points.reserve(mesh.points.size() + static_cast<size_t>(plausible));
        if (lay.role == PlyRole::face) mesh.triangles.reserve(mesh.triangles.size() + static_cast<size_t>(plausible));

        for (long long i = 0; i < el.count; ++i) {
            r.at(el.name, i);
            double xyz[3] = {0, 0, 0};
            double extra_value = 0;
            for (size_t j = 0; j < el.props.size(); ++j) {
                const PlyProperty& prop = el.props[j];
                const int idx = static_cast<int>(j);
                if (prop.is_list) {
                    long long n = 0;
                    if (!r.integer(prop.count_type, n)) truncated(i);
                    if (n < 0)
                        fail(path, "PLY element '" + el.name + "' " + std::to_string(i) + ": negative list length " +
                                       std::to_string(n) + " of property '" + prop.name + "'");
                    if (idx != lay.connectivity) {
                        if (!r.skip(prop.type, n)) truncated(i);
                        continue;
                    }
                    corners.clear();
                    for (long long k = 0; k < n; ++k) {
                        long long v = 0;
                        if (!r.integer(prop.type, v)) truncated(i);
                        corners.push_back(to_index(v));
                    }
                    if (lay.role == PlyRole::face) add_polygon(corners, mesh, info);
                    else add_strips(corners, mesh, info);
                } else if (idx == lay.x || idx == lay.y || idx == lay.z) {
                    if (!r.number(prop.type, xyz[idx == lay.x ? 0 : (idx == lay.y ? 1 : 2)])) truncated(i);
                } else if (idx == extra) {
                    if (!r.number(prop.type, extra_value)) truncated(i);
                } else if (!r.skip(prop.type)) {
                    truncated(i);
                }
            }
            if (lay.role == PlyRole::vertex) mesh.points.push_back({xyz[0], xyz[1], xyz[2]});
            if (extra >= 0 && !std::isfinite(extra_value))
                fail(path, "PLY element '" + el.name + "' " + std::to_string(i) + ": property '" + el.props[extra].name +
                               "' is " + (std::isnan(extra_value) ? "NaN" : "infinite") + "; write a finite value");
            if (extra >= 0 && lay.role == PlyRole::vertex) {
                // Converting a double outside float's range to float is undefined behaviour.
                if (std::fabs(extra_value) > std::numeric_limits<float>::max())
                    fail(path, "PLY element 'vertex' " + std::to_string(i) + ": property '" + el.props[extra].name +
                                   "' = " + short_number(extra_value) + " is out of the range of a float");
                extras->vertex_floats.push_back(static_cast<float>(extra_value));
            }
            if (extra >= 0 && lay.role == PlyRole::face) {
                if (!(extra_value >= -2147483648.0 && extra_value <= 2147483647.0))
                    fail(path, "PLY element 'face' " + std::to_string(i) + ": property '" + el.props[extra].name +
                                   "' = " + short_number(extra_value) + " is out of the range of an int");
                // One value per triangle of the polygon's fan.
                extras->face_ints.resize(mesh.triangles.size(), static_cast<int>(extra_value));
            }
        }
    }
}

void read_ply(const std::string& path, std::string_view data, Mesh& mesh, ReadInfo& info, PlyExtras* extras) {
    const PlyHeader h = parse_ply_header(path, data);
    if (h.encoding == PlyEncoding::ascii) {
        info.format = "ply-ascii";
        PlyAsciiReader r(path, data, h.data_offset, h.data_line);
        read_ply_body(path, h, "ASCII", r, mesh, info, extras);
    } else {
        const bool big = h.encoding == PlyEncoding::binary_be;
        info.format = big ? "ply-binary-be" : "ply-binary-le";
        PlyBinaryReader r(data, h.data_offset, big);
        read_ply_body(path, h, big ? "binary big-endian" : "binary little-endian", r, mesh, info, extras);
    }
}

// ------------------------------------------------------------------------------------------------
// Format detection

enum class Format { obj, ply, off, stl_ascii, stl_binary, unknown };

bool is_obj_keyword(std::string_view tok) {
    static const char* const keys[] = {"v", "vt", "vn", "vp", "f", "l", "p", "g", "o", "s", "usemtl", "mtllib"};
    for (const char* k : keys)
        if (tok == k) return true;
    return false;
}

// Content decides; the extension only breaks ties (e.g. an OBJ that starts with an odd statement,
// an OFF without its header, a broken binary STL).
Format detect_format(std::string_view data, const std::string& ext) {
    if (data.size() >= 3 && data.substr(0, 3) == "ply" && (data.size() == 3 || data[3] == '\n' || data[3] == '\r'))
        return Format::ply;
    if (is_binary_stl_size(data)) return Format::stl_binary;
    TextCursor c(data.data(), data.data() + data.size());
    c.skip_space(true);
    const std::string_view first = c.token();
    // ASCII STL never holds NUL bytes; a binary one whose header says "solid" usually does.
    const bool has_nul = std::memchr(data.data(), 0, data.size()) != nullptr;
    if (first == "solid") return has_nul ? Format::stl_binary : Format::stl_ascii;
    if (is_off_keyword(first)) return Format::off;
    if (is_obj_keyword(first)) return Format::obj;
    if (ext == ".obj") return Format::obj;
    if (ext == ".off") return Format::off;
    if (ext == ".ply") return Format::ply;
    if (ext == ".stl") return has_nul || first.substr(0, 5) != "solid" ? Format::stl_binary : Format::stl_ascii;
    return Format::unknown;
}

// ------------------------------------------------------------------------------------------------
// Writing

// Everything is built in memory and written at once to path.tmp, then renamed over path: a crash
// or a full disk never leaves a half-written file under the real name.
void write_atomically(const std::string& path, std::string_view bytes) {
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) fail(path, "cannot open '" + tmp + "' for writing (" + std::strerror(errno) + ")");
    bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    int err = ok ? 0 : errno;
    if (std::fflush(f) != 0 && ok) {
        ok = false;
        err = errno;
    }
    if (std::fclose(f) != 0 && ok) {
        ok = false;
        err = errno;
    }
    if (!ok) {
        std::remove(tmp.c_str());
        fail(path, "cannot write '" + tmp + "' (" + std::strerror(err) + ")");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        err = errno;
        std::remove(tmp.c_str());
        fail(path, "cannot rename '" + tmp + "' to the final name (" + std::strerror(err) + ")");
    }
}

class ByteWriter {
public:
    explicit ByteWriter(std::string& out) : out_(out), swap_(!host_is_little_endian()) {}

    template <class T>
    void put(T v) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (swap_) std::reverse(b, b + sizeof(T));
        out_.append(b, sizeof(T));
    }

private:
    std::string& out_;
    bool swap_;
};

// %.17g: enough digits for every double to read back bit-identical.
void append_double(std::string& out, double v) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
    out.append(buf, r.ptr);
}

// Shortest representation that reads back as the same float.
void append_float(std::string& out, float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

void append_int(std::string& out, long long v) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

void check_property_name(const std::string& path, const std::string& name, const char* element,
                         std::initializer_list<const char*> taken) {
    const bool blank = std::any_of(name.begin(), name.end(), [](char ch) {
        return std::isspace(static_cast<unsigned char>(ch)) != 0 || !std::isprint(static_cast<unsigned char>(ch));
    });
    if (blank) fail(path, std::string("PLY ") + element + " property name " + quote(name) + " must be printable without spaces");
    for (const char* t : taken)
        if (name == t) fail(path, std::string("PLY ") + element + " property name " + quote(name) + " clashes with a standard property");
}

void check_extras(const std::string& path, const Mesh& mesh, const PlyExtras& extras) {
    if (!extras.face_int_name.empty()) {
        check_property_name(path, extras.face_int_name, "face", {"vertex_indices", "vertex_index"});
        if (extras.face_ints.size() != mesh.triangles.size())
            fail(path, "face property '" + extras.face_int_name + "' has " + std::to_string(extras.face_ints.size()) +
                           " values for " + std::to_string(mesh.triangles.size()) + " triangles");
    } else if (!extras.face_ints.empty()) {
        fail(path, std::to_string(extras.face_ints.size()) + " face values given without a property name (PlyExtras::face_int_name)");
    }
    if (!extras.vertex_float_name.empty()) {
        check_property_name(path, extras.vertex_float_name, "vertex", {"x", "y", "z"});
        if (extras.vertex_floats.size() != mesh.points.size())
            fail(path, "vertex property '" + extras.vertex_float_name + "' has " + std::to_string(extras.vertex_floats.size()) +
                           " values for " + std::to_string(mesh.points.size()) + " vertices");
    } else if (!extras.vertex_floats.empty()) {
        fail(path, std::to_string(extras.vertex_floats.size()) +
                       " vertex values given without a property name (PlyExtras::vertex_float_name)");
    }
}

}  // namespace

namespace {

// read_mesh(), read_ply_with_extras() and read_polygon_mesh(): `extras` non-null only for the
// second (PLY only), `polygon_sizes` only for the third.
Mesh read_any(const std::string& path, LoadInfo* info, PlyExtras* extras, std::vector<int>* polygon_sizes = nullptr) {
    const std::string data = read_whole_file(path);
    if (data.find_first_not_of(" \t\r\n\v\f") == std::string::npos)
        fail(path, data.empty() ? "file is empty: contains no triangles" : "file holds only whitespace: contains no triangles");

    std::string_view body(data);
    // A UTF-8 byte order mark in front of a text format (some Windows tools write one).
    if (body.substr(0, 3) == "\xEF\xBB\xBF" && !is_binary_stl_size(body)) body.remove_prefix(3);

    const std::string ext = lower_extension(path);
    Mesh mesh;
    ReadInfo li;
    li.polygon_sizes = polygon_sizes;
    switch (detect_format(body, ext)) {
        case Format::obj: li.format = "obj"; read_obj(path, body, mesh, li); break;
        case Format::off: li.format = "off"; read_off(path, body, mesh, li); break;
        case Format::ply: read_ply(path, body, mesh, li, extras); break;
        case Format::stl_ascii: li.format = "stl-ascii"; read_stl_ascii(path, body, mesh, li); break;
        case Format::stl_binary: li.format = "stl-binary"; read_stl_binary(path, data, mesh, li); break;
        case Format::unknown:
            fail(path, "unrecognised mesh format" + (ext.empty() ? std::string() : " (extension '" + ext + "')") +
                           "; supported formats: OBJ (.obj), PLY ascii/binary (.ply), OFF (.off), STL ascii/binary (.stl)");
    }
    if (mesh.triangles.empty()) {
        std::string what = "contains no triangles (" + li.format + ": " + std::to_string(mesh.points.size()) + " vertices";
        if (li.dropped_faces > 0) what += ", " + std::to_string(li.dropped_faces) + " faces with fewer than 3 corners";
        fail(path, what + ")");
    }
    if (mesh.points.empty())
        fail(path, "contains " + std::to_string(mesh.triangles.size()) + " triangles but no vertices (" + li.format + ")");
    if (info) *info = li;
    return mesh;
}

}  // namespace

Mesh read_mesh(const std::string& path, LoadInfo* info) { return read_any(path, info, nullptr); }

PolygonMesh read_polygon_mesh(const std::string& path, LoadInfo* info) {
    std::vector<int> sizes;
    const Mesh fans = read_any(path, info, nullptr, &sizes);
    PolygonMesh out;
    out.points = fans.points;
    out.faces.reserve(sizes.size());
    size_t t = 0;
    for (const int n : sizes) {
        // The fan of a polygon c0..c(n-1) is (c0, c1, c2), (c0, c2, c3), ...: its first triangle
        // gives three corners, each further one the next corner.
        QC_CHECK(t + (n - 2) <= fans.triangles.size(), "read_polygon_mesh: fan bookkeeping");
        std::vector<int> face{fans.triangles[t][0], fans.triangles[t][1], fans.triangles[t][2]};
        for (int k = 1; k < n - 2; ++k) face.push_back(fans.triangles[t + k][2]);
        t += n - 2;
        out.faces.push_back(std::move(face));
    }
    QC_CHECK(t == fans.triangles.size(), "read_polygon_mesh: fan bookkeeping");
    return out;
}

Mesh read_ply_with_extras(const std::string& path, PlyExtras& extras, LoadInfo* info) {
    extras.face_ints.clear();
    extras.vertex_floats.clear();
    LoadInfo li;
    Mesh mesh = read_any(path, &li, &extras);
    if (li.format.rfind("ply", 0) != 0)
        fail(path, "is a " + li.format + " file, not a PLY: per-face and per-vertex properties are read from PLY only");
    // A property counts as present only if it covers every triangle (vertex): e.g. a second face
    // element without it makes it absent.
    if (!extras.face_ints.empty() && extras.face_ints.size() != mesh.triangles.size()) extras.face_ints.clear();
    if (!extras.vertex_floats.empty() && extras.vertex_floats.size() != mesh.points.size()) extras.vertex_floats.clear();
    if (info) *info = li;
    return mesh;
}

void write_ply(const std::string& path, const Mesh& mesh, const PlyExtras& extras, bool ascii) {
    check_extras(path, mesh, extras);
    const bool vertex_extra = !extras.vertex_float_name.empty();
    const bool face_extra = !extras.face_int_name.empty();

    std::string out = "ply\nformat ";
    out += ascii ? "ascii" : "binary_little_endian";
    out += " 1.0\ncomment written by quadcage\nelement vertex " + std::to_string(mesh.points.size()) +
           "\nproperty double x\nproperty double y\nproperty double z\n";
    if (vertex_extra) out += "property float " + extras.vertex_float_name + "\n";
    out += "element face " + std::to_string(mesh.triangles.size()) + "\nproperty list uchar int vertex_indices\n";
    if (face_extra) out += "property int " + extras.face_int_name + "\n";
    out += "end_header\n";

    if (ascii) {
        out.reserve(out.size() + mesh.points.size() * 60 + mesh.triangles.size() * 24);
        for (size_t i = 0; i < mesh.points.size(); ++i) {
            const Vec3& p = mesh.points[i];
            append_double(out, p.x);
            out += ' ';
            append_double(out, p.y);
            out += ' ';
            append_double(out, p.z);
            if (vertex_extra) {
                out += ' ';
                append_float(out, extras.vertex_floats[i]);
            }
            out += '\n';
        }
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            out += '3';
            for (int v : mesh.triangles[t]) {
                out += ' ';
                append_int(out, v);
            }
            if (face_extra) {
                out += ' ';
                append_int(out, extras.face_ints[t]);
            }
            out += '\n';
        }
    } else {
        out.reserve(out.size() + mesh.points.size() * (24 + 4) + mesh.triangles.size() * (13 + 4));
        ByteWriter w(out);
        for (size_t i = 0; i < mesh.points.size(); ++i) {
            const Vec3& p = mesh.points[i];
            w.put(p.x);
            w.put(p.y);
            w.put(p.z);
            if (vertex_extra) w.put(extras.vertex_floats[i]);
        }
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            w.put(static_cast<std::uint8_t>(3));
            for (int v : mesh.triangles[t]) w.put(static_cast<std::int32_t>(v));
            if (face_extra) w.put(static_cast<std::int32_t>(extras.face_ints[t]));
        }
    }
    write_atomically(path, out);
}

void write_obj(const std::string& path, const Mesh& mesh) {
    std::string out = "# written by quadcage\n";
    out.reserve(out.size() + mesh.points.size() * 64 + mesh.triangles.size() * 24);
    for (const Vec3& p : mesh.points) {
        out += "v ";
        append_double(out, p.x);
        out += ' ';
        append_double(out, p.y);
        out += ' ';
        append_double(out, p.z);
        out += '\n';
    }
    for (const Triangle& t : mesh.triangles) {
        out += 'f';
        for (int v : t) {
            out += ' ';
            append_int(out, static_cast<long long>(v) + 1);
        }
        out += '\n';
    }
    write_atomically(path, out);
}

void write_text_file(const std::string& path, const std::string& text) { write_atomically(path, text); }

}  // namespace quadcage
