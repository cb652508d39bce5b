#include "maxslice/mesh/triangle_mesh.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <utility>

#include "maxslice/core/assert.hpp"
#include "maxslice/core/union_find.hpp"
#include "mesh_detail.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace maxslice::mesh {
namespace {

// Asks the kernel to back [p, p + bytes) with transparent huge pages where it can. The large
// buffers of a weld are touched once each, so with 4 KiB pages the page faults cost more than
// the hashing itself (measured: over half the time for 2M triangles).
void advise_huge_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t kHuge = 2u << 20;
    const auto begin = (reinterpret_cast<std::uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
    const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHuge - 1);
    if (end > begin) {
        (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
    }
#else
    (void)p;
    (void)bytes;
#endif
}

// A zero-filled array of T (trivial types) that is not value-initialised element by element
// and whose pages may be huge.
template <class T>
class HugeArray {
public:
    explicit HugeArray(std::size_t n) : n_(n) {
        // Small tables (most meshes) stay small: huge-page alignment only pays from 2 MiB.
        constexpr std::size_t kHuge = 2u << 20;
        const std::size_t wanted = std::max<std::size_t>(n * sizeof(T), 64);
        const std::size_t align = wanted >= kHuge ? kHuge : 64;
        const std::size_t bytes = (wanted + align - 1) / align * align;
        data_ = static_cast<T*>(std::aligned_alloc(align, bytes));
        if (data_ == nullptr) throw std::bad_alloc();  // as std::vector would
        if (align == kHuge) advise_huge_pages(data_, bytes);
        std::memset(static_cast<void*>(data_), 0, bytes);
    }
    HugeArray(const HugeArray&) = delete;
    HugeArray& operator=(const HugeArray&) = delete;
    HugeArray(HugeArray&& o) noexcept : data_(std::exchange(o.data_, nullptr)), n_(o.n_) {}
    HugeArray& operator=(HugeArray&& o) noexcept {
        std::swap(data_, o.data_);
        std::swap(n_, o.n_);
        return *this;
    }
    ~HugeArray() { std::free(data_); }
    T& operator[](std::size_t i) { return data_[i]; }
    [[nodiscard]] std::size_t size() const { return n_; }

private:
    T* data_ = nullptr;
    std::size_t n_ = 0;
};

// Exact weld: an open-addressing (linear probing) hash table keyed on the coordinate bit
// patterns. Each slot stores the key inline next to the vertex index, so a lookup touches one
// cache line, and the slot of a corner a few places ahead is prefetched while the current
// one is resolved: the table is much larger than the cache for big meshes and the lookups
// are otherwise latency-bound. The table starts sized for a closed mesh (about one vertex per
// six corners) and doubles at load 1/2, which only happens for soups.
template <class Bits>
struct WeldSlot {
    Bits key[3];
    std::uint32_t index_plus_one;  // 0 when free (so a zeroed table is empty)
};

constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();

inline std::uint64_t mix64(std::uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    h ^= h >> 33;
    return h;
}

template <class Bits>
inline std::uint64_t hash_key(const Bits (&k)[3]) {
    if constexpr (sizeof(Bits) == 4) {
        const std::uint64_t a = (static_cast<std::uint64_t>(k[0]) << 32) | k[1];
        return mix64(a * 0x9e3779b97f4a7c15ULL + k[2]);
    } else {
        return mix64(mix64(k[0] * 0x9e3779b97f4a7c15ULL + k[1]) + k[2]);
    }
}

// The weld of a soup handed over in blocks of whole triangles: the table and the mesh live
// across blocks, so the result is the same as one pass over the whole soup.
template <class Real>
class Welder {
    using Bits = std::conditional_t<sizeof(Real) == 4, std::uint32_t, std::uint64_t>;
    using Slot = WeldSlot<Bits>;
    static constexpr Bits kNegZero = Bits{1} << (sizeof(Bits) * 8 - 1);

public:
    explicit Welder(std::size_t tris)
        : capacity_(std::bit_ceil(std::max<std::size_t>(64, tris))),
          table_(capacity_),
          mask_(capacity_ - 1),
          grow_at_(capacity_ / 2) {
        MAXSLICE_ASSERT(tris * 3 < kEmpty);
        mesh_.triangles.reserve(tris);
        advise_huge_pages(mesh_.triangles.data(), tris * sizeof(Triangle));
        mesh_.triangles.resize(tris);
        mesh_.vertices.reserve(tris * 3 / 5 + 16);
        advise_huge_pages(mesh_.vertices.data(), mesh_.vertices.capacity() * sizeof(core::Vec3d));
    }

    // Adds the whole triangles of xyz (9 numbers each) after those added before.
    void add(std::span<const Real> xyz) {
        const std::size_t corners = xyz.size() / 9 * 3;
        if (corners == 0) return;
        MAXSLICE_ASSERT(done_ + corners <= mesh_.triangles.size() * 3);
        auto key_of = [&](std::size_t c, Bits(&k)[3]) {
            std::memcpy(k, xyz.data() + 3 * c, sizeof(k));
            for (Bits& b : k) {
                if (b == kNegZero) b = 0;  // -0.0 and 0.0 are the same position
            }
        };
        constexpr std::size_t kAhead = 16;
        std::uint64_t hashes[kAhead];
        for (std::size_t c = 0; c < std::min(kAhead, corners); ++c) {
            Bits k[3];
            key_of(c, k);
            hashes[c] = hash_key(k);
            __builtin_prefetch(&table_[hashes[c] & mask_]);
        }
        std::uint32_t* out = mesh_.triangles.front().data() + done_;
        for (std::size_t c = 0; c < corners; ++c) {
            Bits k[3];
            key_of(c, k);
            const std::uint64_t h = hashes[c % kAhead];
            if (c + kAhead < corners) {
                Bits ahead[3];
                key_of(c + kAhead, ahead);
                const std::uint64_t ha = hash_key(ahead);
                hashes[c % kAhead] = ha;
                __builtin_prefetch(&table_[ha & mask_]);
            }
            out[c] = index_of(k, h);
        }
        done_ += corners;
    }

    // The mesh of the triangles added (fewer than announced if the soup ended early).
    TriangleMesh finish() {
        mesh_.triangles.resize(done_ / 3);
        return std::move(mesh_);
    }

private:
    // The vertex of position k (hash h), a new one if k is new. A hash computed before a
    // grow is still right: the slot is taken from h with the current mask.
    std::uint32_t index_of(const Bits (&k)[3], std::uint64_t h) {
        std::size_t i = h & mask_;
        while (true) {
            const Slot& s = table_[i];
            if (s.index_plus_one == 0) break;
            if (s.key[0] == k[0] && s.key[1] == k[1] && s.key[2] == k[2]) {
                return s.index_plus_one - 1;
            }
            i = (i + 1) & mask_;
        }
        const auto found = static_cast<std::uint32_t>(mesh_.vertices.size());
        Slot& s = table_[i];
        std::memcpy(s.key, k, sizeof(k));
        s.index_plus_one = found + 1;
        Real p[3];
        std::memcpy(p, k, sizeof(p));
        mesh_.vertices.push_back(
            {static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])});
        if (mesh_.vertices.size() > grow_at_) grow();
        return found;
    }

    void grow() {
        HugeArray<Slot> bigger(capacity_ * 2);
        const std::size_t bigger_mask = capacity_ * 2 - 1;
        for (std::size_t j = 0; j < capacity_; ++j) {
            const Slot& s = table_[j];
            if (s.index_plus_one == 0) continue;
            std::size_t i = hash_key(s.key) & bigger_mask;
            while (bigger[i].index_plus_one != 0) i = (i + 1) & bigger_mask;
            bigger[i] = s;
        }
        table_ = std::move(bigger);
        capacity_ *= 2;
        mask_ = bigger_mask;
        grow_at_ = capacity_ / 2;
    }

    TriangleMesh mesh_;
    std::size_t capacity_;
    HugeArray<Slot> table_;
    std::size_t mask_;
    std::size_t grow_at_;
    std::size_t done_ = 0;  // corners added
};

template <class Real>
TriangleMesh weld_impl(std::span<const Real> xyz) {
    // A trailing partial triangle (fewer than 9 numbers) is ignored.
    const std::size_t tris = xyz.size() / 9;
    if (tris == 0) return {};
    Welder<Real> welder(tris);
    welder.add(xyz);
    return welder.finish();
}

}  // namespace

core::Box3d bounding_box(const TriangleMesh& mesh) {
    core::Box3d box;
    if (mesh.triangles.empty()) return box;
    // Only used vertices count; marking them first keeps the min/max loop linear in the
    // vertices rather than in the (three times more) corners.
    std::vector<std::uint8_t> used(mesh.vertices.size(), 0);
    for (const Triangle& t : mesh.triangles) {
        for (std::uint32_t v : t) {
            MAXSLICE_ASSERT(v < mesh.vertices.size());
            used[v] = 1;
        }
    }
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (used[v]) box.add(mesh.vertices[v]);
    }
    return box;
}

double signed_volume(const TriangleMesh& mesh) {
    if (mesh.triangles.empty()) return 0.0;
    // Tetrahedra are taken from the first vertex rather than the origin: the result is the
    // same for a closed surface, and parts far from the origin lose less to cancellation.
    const core::Vec3d o = mesh.vertices[mesh.triangles.front()[0]];
    const double six_v = detail::deterministic_sum(mesh.triangles.size(), [&](std::size_t t) {
        const Triangle& tri = mesh.triangles[t];
        return detail::six_volume_term(o, mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                       mesh.vertices[tri[2]]);
    });
    return six_v / 6.0;
}

double surface_area(const TriangleMesh& mesh) {
    return 0.5 * detail::deterministic_sum(mesh.triangles.size(), [&](std::size_t t) {
               const Triangle& tri = mesh.triangles[t];
               return detail::twice_area_term(mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                              mesh.vertices[tri[2]]);
           });
}

core::Vec3d area_vector(const TriangleMesh& mesh, std::size_t tri) {
    const Triangle& t = mesh.triangles[tri];
    const core::Vec3d& a = mesh.vertices[t[0]];
    return core::cross(mesh.vertices[t[1]] - a, mesh.vertices[t[2]] - a);
}

void scale(TriangleMesh& mesh, double s) {
    for (core::Vec3d& v : mesh.vertices) v = v * s;
}

void transform(TriangleMesh& mesh, const std::array<double, 12>& m) {
    for (core::Vec3d& v : mesh.vertices) {
        v = {m[0] * v.x + m[1] * v.y + m[2] * v.z + m[3],
             m[4] * v.x + m[5] * v.y + m[6] * v.z + m[7],
             m[8] * v.x + m[9] * v.y + m[10] * v.z + m[11]};
    }
    const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                       m[2] * (m[4] * m[9] - m[5] * m[8]);
    if (det < 0.0) {
        for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
    }
}

std::vector<core::Vec3d> surface_samples(const TriangleMesh& mesh, double spacing_mm) {
    std::vector<core::Vec3d> out;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const core::Vec3d a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
        const double longest = std::max({core::norm(b - a), core::norm(c - b), core::norm(a - c)});
        const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing_mm)));
        for (int i = 0; i <= n; ++i) {
            for (int j = 0; i + j <= n; ++j) {
                const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
                out.push_back(a + (b - a) * u + (c - a) * v);
            }
        }
    }
    return out;
}

std::vector<std::uint32_t> vertex_bodies(const TriangleMesh& mesh) {
    constexpr std::size_t kPrefetchAhead = 8;
    core::UnionFind sets(mesh.vertices.size());
    const std::size_t nt = mesh.triangles.size();
    for (std::size_t i = 0; i < nt; ++i) {
        const Triangle& t = mesh.triangles[i];
        if (i + kPrefetchAhead < nt) {
            for (std::uint32_t w : mesh.triangles[i + kPrefetchAhead]) sets.prefetch(w);
        }
        MAXSLICE_ASSERT(t[0] < sets.size() && t[1] < sets.size() && t[2] < sets.size());
        sets.unite(t[0], t[1]);
        sets.unite(t[0], t[2]);
    }
    std::vector<std::uint32_t> body(mesh.vertices.size());
    for (std::size_t v = 0; v < body.size(); ++v)
        body[v] = sets.find(static_cast<std::uint32_t>(v));
    return body;
}

void append(TriangleMesh& a, const TriangleMesh& b) {
    MAXSLICE_ASSERT(a.vertices.size() + b.vertices.size() < kEmpty);
    const auto offset = static_cast<std::uint32_t>(a.vertices.size());
    a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
    a.triangles.reserve(a.triangles.size() + b.triangles.size());
    for (const Triangle& t : b.triangles) {
        a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    }
}

TriangleMesh weld_exact(std::span<const float> xyz) {
    return weld_impl(xyz);
}

struct BlockWelder::Impl {
    explicit Impl(std::size_t triangles) : welder(triangles) {}
    Welder<float> welder;
};

BlockWelder::BlockWelder(std::size_t triangles) : impl_(std::make_unique<Impl>(triangles)) {}
BlockWelder::~BlockWelder() = default;
BlockWelder::BlockWelder(BlockWelder&&) noexcept = default;
BlockWelder& BlockWelder::operator=(BlockWelder&&) noexcept = default;

void BlockWelder::add(std::span<const float> xyz) {
    impl_->welder.add(xyz);
}

TriangleMesh BlockWelder::finish() && {
    return impl_->welder.finish();
}
TriangleMesh weld_exact(std::span<const double> xyz) {
    return weld_impl(xyz);
}

TriangleMesh placed_on_plate(TriangleMesh part, const core::Vec3d& direction,
                             const core::Vec3d& plate_center) {
    // Rodrigues rotation taking d onto +Z (a half turn about X when d points down).
    const core::Vec3d d = core::normalized(direction);
    const core::Vec3d z{0.0, 0.0, 1.0};
    const core::Vec3d axis = core::cross(d, z);
    const double s = core::norm(axis), c = core::dot(d, z);
    std::array<double, 12> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    if (s > 1e-12) {
        const core::Vec3d k = axis / s;
        const double v = 1.0 - c;
        m = {c + k.x * k.x * v,       k.x * k.y * v - k.z * s, k.x * k.z * v + k.y * s, 0.0,
             k.y * k.x * v + k.z * s, c + k.y * k.y * v,       k.y * k.z * v - k.x * s, 0.0,
             k.z * k.x * v - k.y * s, k.z * k.y * v + k.x * s, c + k.z * k.z * v,       0.0};
    } else if (c < 0.0) {
        m = {1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0};
    }
    transform(part, m);
    const core::Box3d box = bounding_box(part);
    if (!box.empty()) {
        transform(part, {1, 0, 0, plate_center.x - box.center().x, 0, 1, 0,
                         plate_center.y - box.center().y, 0, 0, 1, -box.min.z});
    }
    return part;
}

}  // namespace maxslice::mesh
