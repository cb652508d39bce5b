// 3MF through lib3mf 1.8.1's plain-C interface (NMR_DLLInterfaces.h): it returns error codes
// instead of throwing, and every object it hands out is reference counted and released here.
//
// The part is every build item, each with its transform, where an item may be a mesh
// object or a components object whose components (nested to any depth) carry their own
// transforms. 3MF transforms are affine with the translation in the last row for row
// vectors; lib3mf hands them over transposed, as m_fFields[row][col] = [R | t] for column
// vectors, which is the layout mesh::transform uses. Mirroring transforms (negative
// determinant) reverse the corner order so the outside stays outside.

#include <Model/COM/NMR_DLLInterfaces.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

using Affine = std::array<double, 12>;  // row-major [R | t], column vectors

constexpr Affine kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
constexpr int kMaxComponentDepth = 32;
// Components can place one object many times at every level; this bounds the soup (1.4 GB
// of coordinates while reading, ten times the largest part maxslice is measured on).
constexpr std::uint64_t kMaxPlacedTriangles = 20'000'000;

// Owns one lib3mf instance.
class Handle {
public:
    Handle() = default;
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle() {
        if (p_ != nullptr) NMR::lib3mf_release(p_);
    }
    NMR::PLib3MFBase** out() { return &p_; }
    [[nodiscard]] NMR::PLib3MFBase* get() const { return p_; }

private:
    NMR::PLib3MFBase* p_ = nullptr;
};

Affine compose(const Affine& outer, const Affine& inner) {
    Affine r{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            double s = (j == 3) ? outer[static_cast<std::size_t>(4 * i + 3)] : 0.0;
            for (int k = 0; k < 3; ++k) {
                s += outer[static_cast<std::size_t>(4 * i + k)] *
                     inner[static_cast<std::size_t>(4 * k + j)];
            }
            r[static_cast<std::size_t>(4 * i + j)] = s;
        }
    }
    return r;
}

Affine from_lib3mf(const NMR::MODELTRANSFORM& t) {
    Affine a{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            a[static_cast<std::size_t>(4 * i + j)] = static_cast<double>(t.m_fFields[i][j]);
        }
    }
    return a;
}

double determinant(const Affine& a) {
    return a[0] * (a[5] * a[10] - a[6] * a[9]) - a[1] * (a[4] * a[10] - a[6] * a[8]) +
           a[2] * (a[4] * a[9] - a[5] * a[8]);
}

std::optional<core::LengthUnit> unit_of(DWORD unit) {
    switch (unit) {
        case NMR::MODELUNIT_MICROMETER: return core::LengthUnit::kMicron;
        case NMR::MODELUNIT_MILLIMETER: return core::LengthUnit::kMillimetre;
        case NMR::MODELUNIT_CENTIMETER: return core::LengthUnit::kCentimetre;
        case NMR::MODELUNIT_INCH: return core::LengthUnit::kInch;
        case NMR::MODELUNIT_FOOT: return core::LengthUnit::kFoot;
        case NMR::MODELUNIT_METER: return core::LengthUnit::kMetre;
        default: return std::nullopt;
    }
}

std::string last_error(NMR::PLib3MFBase* instance, const char* doing) {
    DWORD code = 0;
    LPCSTR text = nullptr;
    if (instance != nullptr) NMR::lib3mf_getlasterror(instance, &code, &text);
    if (text != nullptr && *text != '\0') {
        return fmt::format("{}: {} (lib3mf error 0x{:X})", doing, text, code);
    }
    return fmt::format("{} (lib3mf error 0x{:X})", doing, code);
}

std::unexpected<core::Error> invalid(std::string message) {
    return core::fail(core::ErrorCode::kInvalidInput, std::move(message));
}

// One object resource as the build uses it, read from lib3mf once however often it is placed.
struct ObjectInfo {
    enum class Kind { kMesh, kComponents, kSkipped, kOther };
    Kind kind = Kind::kOther;
    std::vector<NMR::MODELMESHVERTEX> vertices;
    std::vector<NMR::MODELMESHTRIANGLE> triangles;
    struct Component {
        DWORD target = 0;
        Affine local = kIdentity;
    };
    std::vector<Component> components;
    bool done = false;  // false while its components are being read: a cycle
    int height = 0;     // nesting levels below it
    // Triangles and mesh placements once every component is expanded (saturating).
    std::uint64_t expanded_triangles = 0;
    std::uint64_t expanded_meshes = 0;
};

std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
    return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}

// Components let one object place another many times at every level: 30 levels that each
// place the next twice make a 1.5 KB file of 2^30 placements. The collector therefore reads
// every object once (lib3mf is asked about each object once, not once per placement), counts
// what the build expands to from those counts (linear in the number of objects and
// components), refuses a build that expands past kMaxPlacedTriangles before placing
// anything, and then places only subtrees that hold triangles, so the placing work is
// proportional to the triangles it writes.
class Collector {
public:
    std::size_t skipped_objects = 0;  // support, surface and "other" objects (distinct)
    std::size_t beam_objects = 0;

    // Reads the object and everything its components refer to; returns its resource id.
    core::Result<DWORD> load(NMR::PLib3MFBase* object, int depth) {
        DWORD id = 0;
        if (NMR::lib3mf_resource_getresourceid(object, &id) != LIB3MF_OK) {
            return invalid(last_error(object, "cannot read an object's id"));
        }
        if (const auto it = objects_.find(id); it != objects_.end()) {
            if (!it->second.done || depth + it->second.height > kMaxComponentDepth) {
                return too_deep();
            }
            return id;
        }
        if (depth > kMaxComponentDepth) return too_deep();
        objects_.emplace(id, ObjectInfo{});
        auto info = read_object(object, depth);
        if (!info) return std::unexpected(info.error());
        info->done = true;
        objects_[id] = std::move(*info);
        return id;
    }

    [[nodiscard]] const ObjectInfo& info(DWORD id) const { return objects_.at(id); }

    // Appends the triangles of `id` placed by `world`.
    void place(DWORD id, const Affine& world) {
        const ObjectInfo& o = objects_.at(id);
        if (o.expanded_triangles == 0) return;
        if (o.kind == ObjectInfo::Kind::kMesh) {
            place_mesh(o, world);
            return;
        }
        for (const ObjectInfo::Component& c : o.components)
            place(c.target, compose(world, c.local));
    }

    std::vector<double> xyz;
    std::size_t placed_meshes = 0;

private:
    static std::unexpected<core::Error> too_deep() {
        return invalid(
            fmt::format("components are nested more than {} deep (or refer to each other in "
                        "a cycle)",
                        kMaxComponentDepth));
    }

    core::Result<ObjectInfo> read_object(NMR::PLib3MFBase* object, int depth) {
        ObjectInfo o;
        DWORD type = NMR::MODELOBJECTTYPE_MODEL;
        if (NMR::lib3mf_object_gettype(object, &type) != LIB3MF_OK) {
            return invalid(last_error(object, "cannot read an object's type"));
        }
        if (type != NMR::MODELOBJECTTYPE_MODEL) {
            o.kind = ObjectInfo::Kind::kSkipped;
            ++skipped_objects;
            return o;
        }
        BOOL is_mesh = false;
        BOOL is_components = false;
        if (NMR::lib3mf_object_ismeshobject(object, &is_mesh) != LIB3MF_OK ||
            NMR::lib3mf_object_iscomponentsobject(object, &is_components) != LIB3MF_OK) {
            return invalid(last_error(object, "cannot read an object"));
        }
        if (is_mesh) {
            if (auto ok = read_mesh(object, o); !ok) return std::unexpected(ok.error());
            return o;
        }
        if (!is_components) return o;
        o.kind = ObjectInfo::Kind::kComponents;
        DWORD count = 0;
        if (NMR::lib3mf_componentsobject_getcomponentcount(object, &count) != LIB3MF_OK) {
            return invalid(last_error(object, "cannot read a components object"));
        }
        for (DWORD i = 0; i < count; ++i) {
            Handle component;
            if (NMR::lib3mf_componentsobject_getcomponent(object, i, component.out()) !=
                LIB3MF_OK) {
                return invalid(last_error(object, "cannot read a component"));
            }
            Handle target;
            if (NMR::lib3mf_component_getobjectresource(component.get(), target.out()) !=
                    LIB3MF_OK ||
                target.get() == nullptr) {
                return invalid(last_error(component.get(),
                                          "a component refers to an object that does not exist"));
            }
            ObjectInfo::Component c;
            BOOL has_transform = false;
            NMR::lib3mf_component_hastransform(component.get(), &has_transform);
            if (has_transform) {
                NMR::MODELTRANSFORM t{};
                if (NMR::lib3mf_component_gettransform(component.get(), &t) != LIB3MF_OK) {
                    return invalid(
                        last_error(component.get(), "cannot read a component transform"));
                }
                c.local = from_lib3mf(t);
            }
            auto target_id = load(target.get(), depth + 1);
            if (!target_id) return std::unexpected(target_id.error());
            c.target = *target_id;
            const ObjectInfo& t = objects_.at(c.target);
            o.height = std::max(o.height, t.height + 1);
            o.expanded_triangles = saturating_add(o.expanded_triangles, t.expanded_triangles);
            o.expanded_meshes = saturating_add(o.expanded_meshes, t.expanded_meshes);
            // Only components that hold triangles are kept, so that every step of place()
            // leads to a triangle.
            if (t.expanded_triangles > 0) o.components.push_back(c);
        }
        return o;
    }

    core::Result<void> read_mesh(NMR::PLib3MFBase* object, ObjectInfo& o) {
        o.kind = ObjectInfo::Kind::kMesh;
        DWORD vertex_count = 0;
        DWORD triangle_count = 0;
        if (NMR::lib3mf_meshobject_getvertexcount(object, &vertex_count) != LIB3MF_OK ||
            NMR::lib3mf_meshobject_gettrianglecount(object, &triangle_count) != LIB3MF_OK) {
            return invalid(last_error(object, "cannot read a mesh object"));
        }
        DWORD beams = 0;
        if (NMR::lib3mf_meshobject_getbeamcount(object, &beams) == LIB3MF_OK && beams > 0) {
            ++beam_objects;
        }
        if (triangle_count == 0) return {};
        o.vertices.resize(vertex_count);
        o.triangles.resize(triangle_count);
        DWORD got = 0;
        if ((vertex_count > 0 && NMR::lib3mf_meshobject_getvertices(
                                     object, o.vertices.data(), vertex_count, &got) != LIB3MF_OK) ||
            NMR::lib3mf_meshobject_gettriangleindices(object, o.triangles.data(), triangle_count,
                                                      &got) != LIB3MF_OK) {
            return invalid(last_error(object, "cannot read a mesh object's data"));
        }
        for (const NMR::MODELMESHTRIANGLE& t : o.triangles) {
            for (const DWORD v : t.m_nIndices) {
                if (v >= vertex_count) {
                    return invalid(
                        fmt::format("a triangle refers to vertex {} of a mesh with {} "
                                    "vertices",
                                    v, vertex_count));
                }
            }
        }
        o.expanded_triangles = triangle_count;
        o.expanded_meshes = 1;
        return {};
    }

    void place_mesh(const ObjectInfo& o, const Affine& world) {
        const bool mirrored = determinant(world) < 0.0;
        const bool identity = world == kIdentity;
        const Affine& a = world;
        for (const NMR::MODELMESHTRIANGLE& t : o.triangles) {
            const DWORD order[3] = {t.m_nIndices[0], t.m_nIndices[mirrored ? 2 : 1],
                                    t.m_nIndices[mirrored ? 1 : 2]};
            for (const DWORD v : order) {
                const float* p = o.vertices[v].m_fPosition;
                const double x = p[0], y = p[1], z = p[2];
                if (identity) {
                    xyz.insert(xyz.end(), {x, y, z});
                } else {
                    xyz.insert(xyz.end(), {a[0] * x + a[1] * y + a[2] * z + a[3],
                                           a[4] * x + a[5] * y + a[6] * z + a[7],
                                           a[8] * x + a[9] * y + a[10] * z + a[11]});
                }
            }
        }
        ++placed_meshes;
    }

    std::unordered_map<DWORD, ObjectInfo> objects_;
};

core::Result<RawImport> read_impl(const std::filesystem::path& path) {
    if (auto ok = check_3mf_expansion(path, kMaxPlacedTriangles, kMaxComponentDepth); !ok) {
        return std::unexpected(ok.error());
    }
    Handle model;
    if (NMR::lib3mf_createmodel(model.out()) != LIB3MF_OK || model.get() == nullptr) {
        return invalid("lib3mf could not create a model");
    }
    Handle reader;
    if (NMR::lib3mf_model_queryreader(model.get(), "3mf", reader.out()) != LIB3MF_OK) {
        return invalid(last_error(model.get(), "lib3mf has no 3MF reader"));
    }
    if (NMR::lib3mf_reader_readfromfileutf8(reader.get(), path.c_str()) != LIB3MF_OK) {
        return invalid(last_error(reader.get(), "not a readable 3MF file"));
    }
    RawImport out;
    out.format = Format::k3mf;
    // lib3mf's warnings are spec-conformance notes (mostly about colours and materials,
    // which maxslice ignores): one line with the first is enough.
    DWORD warning_count = 0;
    NMR::lib3mf_reader_getwarningcount(reader.get(), &warning_count);
    if (warning_count > 0) {
        DWORD code = 0;
        ULONG needed = 0;
        std::vector<char> text(1024, '\0');
        std::string first;
        if (NMR::lib3mf_reader_getwarningutf8(reader.get(), 0, &code, text.data(),
                                              static_cast<ULONG>(text.size()),
                                              &needed) == LIB3MF_OK) {
            text.back() = '\0';
            first = text.data();
        }
        out.warnings.push_back(fmt::format("lib3mf reported {} while reading{}",
                                           count_of(warning_count, "non-fatal problem"),
                                           first.empty() ? "" : " (first: " + first + ")"));
    }

    DWORD unit = NMR::MODELUNIT_MILLIMETER;
    if (NMR::lib3mf_model_getunit(model.get(), &unit) != LIB3MF_OK) {
        return invalid(last_error(model.get(), "cannot read the model unit"));
    }
    out.declared_unit = unit_of(unit);
    if (!out.declared_unit) {
        return invalid(fmt::format("unknown 3MF model unit (code {})", unit));
    }
    out.declared_unit_text = std::string(core::unit_name(*out.declared_unit));

    Handle items;
    if (NMR::lib3mf_model_getbuilditems(model.get(), items.out()) != LIB3MF_OK) {
        return invalid(last_error(model.get(), "cannot read the build items"));
    }
    // First every build item's object and what the build expands to; nothing is placed
    // before the whole build is known to fit.
    struct Item {
        DWORD object = 0;
        Affine world = kIdentity;
    };
    std::vector<Item> build;
    Collector collector;
    std::uint64_t total_triangles = 0;
    std::uint64_t total_meshes = 0;
    int deepest = 0;
    while (true) {
        BOOL has_next = false;
        if (NMR::lib3mf_builditemiterator_movenext(items.get(), &has_next) != LIB3MF_OK ||
            !has_next) {
            break;
        }
        Handle item;
        if (NMR::lib3mf_builditemiterator_getcurrent(items.get(), item.out()) != LIB3MF_OK) {
            return invalid(last_error(items.get(), "cannot read a build item"));
        }
        Handle object;
        if (NMR::lib3mf_builditem_getobjectresource(item.get(), object.out()) != LIB3MF_OK ||
            object.get() == nullptr) {
            return invalid(last_error(item.get(), "a build item refers to a missing object"));
        }
        Item placed;
        BOOL has_transform = false;
        NMR::lib3mf_builditem_hasobjecttransform(item.get(), &has_transform);
        if (has_transform) {
            NMR::MODELTRANSFORM t{};
            if (NMR::lib3mf_builditem_getobjecttransform(item.get(), &t) != LIB3MF_OK) {
                return invalid(last_error(item.get(), "cannot read a build item transform"));
            }
            placed.world = from_lib3mf(t);
        }
        auto id = collector.load(object.get(), 0);
        if (!id) return std::unexpected(id.error());
        placed.object = *id;
        const ObjectInfo& info = collector.info(*id);
        total_triangles = saturating_add(total_triangles, info.expanded_triangles);
        total_meshes = saturating_add(total_meshes, info.expanded_meshes);
        deepest = std::max(deepest, info.height);
        build.push_back(placed);
    }
    const std::size_t item_count = build.size();
    if (total_triangles > kMaxPlacedTriangles) {
        return invalid(
            fmt::format("the build places {} triangles once its components are expanded ({} mesh "
                        "placements, components nested {} deep); maxslice reads at most {} placed "
                        "triangles: the file multiplies its objects far beyond a part's size",
                        total_triangles == UINT64_MAX ? std::string("more than 1.8e19")
                                                      : std::to_string(total_triangles),
                        total_meshes == UINT64_MAX ? std::string("more than 1.8e19")
                                                   : std::to_string(total_meshes),
                        deepest, kMaxPlacedTriangles));
    }
    collector.xyz.reserve(9 * static_cast<std::size_t>(total_triangles));
    for (const Item& item : build) collector.place(item.object, item.world);
    if (item_count == 0) {
        return invalid("no triangles: the 3MF build has no items (nothing is placed to print)");
    }
    if (collector.xyz.empty()) {
        return invalid(fmt::format(
            "no triangles: the {} build items hold no mesh triangles{}", item_count,
            collector.skipped_objects > 0 ? " (only support, surface or 'other' objects)" : ""));
    }
    for (const double v : collector.xyz) {
        if (!std::isfinite(v)) {
            return invalid("a vertex has a NaN or infinite coordinate after its transforms");
        }
    }
    if (collector.skipped_objects > 0) {
        out.warnings.push_back(
            fmt::format("ignored {} (only model objects are parts)",
                        count_of(collector.skipped_objects, "support, surface or 'other' object",
                                 "support, surface or 'other' objects")));
    }
    if (collector.beam_objects > 0) {
        out.warnings.push_back(
            fmt::format("{} beam lattices; the beams are ignored, only triangles are read",
                        count_of(collector.beam_objects, "object carries", "objects carry")));
    }
    out.solids = collector.placed_meshes;
    out.mesh = mesh::weld_exact(std::span<const double>(collector.xyz));
    return out;
}

}  // namespace

core::Result<RawImport> read_3mf(const std::filesystem::path& path) {
    try {
        return read_impl(path);
    } catch (const std::bad_alloc&) {
        return invalid("not enough memory for the mesh");
    } catch (const std::exception& e) {
        return invalid(fmt::format("not a readable 3MF file: {}", e.what()));
    } catch (...) {
        return invalid("not a readable 3MF file: lib3mf failed");
    }
}

}  // namespace maxslice::io::detail
