// A first look at a 3MF's model parts before lib3mf reads them. lib3mf 1.8.1 walks every path
// of the component tree while it reads (CModelComponentsObject::isValidForSlices, for each
// build item), so a 2 KB file of 30 levels that each place the next twice costs it 2^30 steps
// before maxslice gets the model. This pass reads the .model parts with minizip and a small
// tag scanner (objects, their triangles and components, and build items; nothing else),
// counts what the build expands to per object (linear in objects plus components), and
// refuses a build beyond the limit before lib3mf starts.
//
// The scan is a conservative bound, not a parser: what it cannot follow (a component that
// names an object it did not find, an id written with character references) counts as an
// empty leaf, and lib3mf, then the collector in lib3mf_reader.cpp, still read and check the
// file as before. A bad zip is left for lib3mf to report.

#include <fmt/format.h>
#include <minizip/unzip.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
    return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}

struct Object {
    std::uint64_t triangles = 0;
    std::vector<std::string> components;  // keys
    // Filled by expand().
    int state = 0;  // 0 new, 1 in progress, 2 done
    int height = 0;
    std::uint64_t expanded_triangles = 0;
    std::uint64_t expanded_placements = 0;
};

// The local name of a tag ("m:object" -> "object") and one attribute's value by local name.
std::string_view local(std::string_view name) {
    const std::size_t colon = name.rfind(':');
    return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

std::string_view attribute(std::string_view tag, std::string_view wanted) {
    std::size_t i = 0;
    while (i < tag.size() && tag[i] != ' ' && tag[i] != '\t' && tag[i] != '\n' && tag[i] != '\r')
        ++i;  // the tag's name
    while (i < tag.size()) {
        while (i < tag.size() && (tag[i] == ' ' || tag[i] == '\t' || tag[i] == '\n' ||
                                  tag[i] == '\r' || tag[i] == '/'))
            ++i;
        const std::size_t name_start = i;
        while (i < tag.size() && tag[i] != '=' && tag[i] != ' ' && tag[i] != '\t' &&
               tag[i] != '\n' && tag[i] != '\r')
            ++i;
        const std::string_view name = tag.substr(name_start, i - name_start);
        while (i < tag.size() && tag[i] != '=') ++i;
        ++i;
        while (i < tag.size() && tag[i] != '"' && tag[i] != '\'') ++i;
        if (i >= tag.size()) return {};
        const char quote = tag[i++];
        const std::size_t value_start = i;
        while (i < tag.size() && tag[i] != quote) ++i;
        const std::string_view value = tag.substr(value_start, i - value_start);
        ++i;
        if (local(name) == wanted) return value;
    }
    return {};
}

std::string normalised_part(std::string_view part) {
    while (!part.empty() && part.front() == '/') part.remove_prefix(1);
    std::string out(part);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

class Scanner {
public:
    explicit Scanner(std::string part) : part_(std::move(part)) {}

    void feed(std::string_view bytes) {
        for (const char c : bytes) {
            if (!in_tag_) {
                if (c == '<') {
                    in_tag_ = true;
                    tag_.clear();
                    last_ = before_last_ = 0;
                }
                continue;
            }
            if (quote_ != 0) {
                if (c == quote_) quote_ = 0;
            } else {
                const bool comment = tag_.starts_with("!--");
                if ((c == '"' || c == '\'') && !tag_.starts_with("!")) quote_ = c;
                if (c == '>' && (!comment || (last_ == '-' && before_last_ == '-'))) {
                    in_tag_ = false;
                    handle(tag_, last_ == '/');
                    continue;
                }
            }
            before_last_ = last_;
            last_ = c;
            // Only the start of a tag matters (its name and attributes); the rest of a huge
            // attribute value or comment is not kept.
            if (tag_.size() < 4096) tag_.push_back(c);
        }
    }

    std::unordered_map<std::string, Object>& objects() { return objects_; }
    std::vector<std::string>& items() { return items_; }

private:
    std::string key(std::string_view id, std::string_view path) const {
        return (path.empty() ? part_ : normalised_part(path)) + "#" + std::string(id);
    }

    void handle(std::string_view tag, bool self_closing) {
        if (tag.empty() || tag.front() == '?' || tag.front() == '!') return;
        const bool closing = tag.front() == '/';
        if (closing) tag.remove_prefix(1);
        std::size_t end = 0;
        while (end < tag.size() && tag[end] != ' ' && tag[end] != '\t' && tag[end] != '\n' &&
               tag[end] != '\r' && tag[end] != '/')
            ++end;
        const std::string_view name = local(tag.substr(0, end));
        if (name == "object") {
            if (closing) {
                current_ = nullptr;
                return;
            }
            current_ = &objects_[key(attribute(tag, "id"), {})];
            if (self_closing) current_ = nullptr;
        } else if (closing) {
            return;
        } else if (name == "triangle" && current_ != nullptr) {
            ++current_->triangles;
        } else if (name == "component" && current_ != nullptr) {
            current_->components.push_back(key(attribute(tag, "objectid"), attribute(tag, "path")));
        } else if (name == "item") {
            items_.push_back(key(attribute(tag, "objectid"), attribute(tag, "path")));
        }
    }

    std::string part_;
    std::unordered_map<std::string, Object> objects_;
    std::vector<std::string> items_;
    Object* current_ = nullptr;
    bool in_tag_ = false;
    char quote_ = 0;
    char last_ = 0;  // the tag's last two characters, kept when the tag itself is cut
    char before_last_ = 0;
    std::string tag_;
};

// Expands one object (memoised); a cycle or an unknown object counts as an empty leaf.
// Recursion is bounded by max_depth: deeper trees are refused by the caller.
bool expand(std::unordered_map<std::string, Object>& objects, Object& o, int depth, int max_depth) {
    if (o.state == 2) return depth + o.height <= max_depth;
    if (o.state == 1) return true;  // a cycle: lib3mf refuses it
    if (depth > max_depth) return false;
    o.state = 1;
    o.expanded_triangles = o.triangles;
    o.expanded_placements = 1;
    for (const std::string& k : o.components) {
        const auto it = objects.find(k);
        if (it == objects.end() || &it->second == &o) continue;
        Object& t = it->second;
        if (!expand(objects, t, depth + 1, max_depth)) return false;
        if (t.state != 2) continue;
        o.height = std::max(o.height, t.height + 1);
        o.expanded_triangles = saturating_add(o.expanded_triangles, t.expanded_triangles);
        o.expanded_placements = saturating_add(o.expanded_placements, t.expanded_placements);
    }
    o.state = 2;
    return true;
}

std::string count_text(std::uint64_t n) {
    return n == UINT64_MAX ? std::string("more than 1.8e19") : std::to_string(n);
}

}  // namespace

core::Result<void> check_3mf_expansion(const std::filesystem::path& path, std::uint64_t max_placed,
                                       int max_depth) {
    unzFile zip = unzOpen64(path.c_str());
    if (zip == nullptr) return {};  // lib3mf reports what is wrong with the zip
    std::unordered_map<std::string, Object> objects;
    std::vector<std::string> items;
    std::vector<char> buffer(1 << 16);
    for (int at = unzGoToFirstFile(zip); at == UNZ_OK; at = unzGoToNextFile(zip)) {
        char name[1024] = {};
        unz_file_info64 info{};
        if (unzGetCurrentFileInfo64(zip, &info, name, sizeof name - 1, nullptr, 0, nullptr, 0) !=
            UNZ_OK) {
            break;
        }
        const std::string part = normalised_part(name);
        if (!part.ends_with(".model") || unzOpenCurrentFile(zip) != UNZ_OK) continue;
        Scanner scanner(part);
        while (true) {
            const int got =
                unzReadCurrentFile(zip, buffer.data(), static_cast<unsigned>(buffer.size()));
            if (got <= 0) break;
            scanner.feed({buffer.data(), static_cast<std::size_t>(got)});
        }
        unzCloseCurrentFile(zip);
        for (auto& [k, o] : scanner.objects()) objects.insert_or_assign(k, std::move(o));
        items.insert(items.end(), scanner.items().begin(), scanner.items().end());
    }
    unzClose(zip);

    std::uint64_t triangles = 0;
    std::uint64_t placements = 0;
    int deepest = 0;
    for (const std::string& k : items) {
        const auto it = objects.find(k);
        if (it == objects.end()) continue;
        if (!expand(objects, it->second, 0, max_depth)) {
            return core::fail(core::ErrorCode::kInvalidInput,
                              fmt::format("components are nested more than {} deep (or refer "
                                          "to each other in a cycle)",
                                          max_depth));
        }
        triangles = saturating_add(triangles, it->second.expanded_triangles);
        placements = saturating_add(placements, it->second.expanded_placements);
        deepest = std::max(deepest, it->second.height);
    }
    if (triangles > max_placed || placements > max_placed) {
        return core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format("the build places {} triangles once its components are expanded ({} "
                        "object placements, components nested {} deep); maxslice reads at most "
                        "{} placed triangles or placements: the file multiplies its objects far "
                        "beyond a part's size",
                        count_text(triangles), count_text(placements), deepest, max_placed));
    }
    return {};
}

}  // namespace maxslice::io::detail
