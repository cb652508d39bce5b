// STEP and IGES through Open CASCADE. Only solids are read: loose faces, open shells and
// wireframe (construction geometry, PMI) are skipped with a warning, and a file with no
// solid is refused. Each solid is tessellated with BRepMesh_IncrementalMesh using the
// options' chord and angular deviation; a face whose orientation is reversed in its solid
// contributes its triangles reversed, and face locations (assembly placements) are applied,
// so the triangles wind counter-clockwise seen from outside.
//
// Open CASCADE converts lengths to mm (xstep.cascade.unit, checked below) and keeps global
// state (static parameters, unit factors, the default messenger), so every use here runs
// under one mutex. This file is a module of its own (libmaxslice_cad.so): read_cad
// (cad_plugin.cpp) loads it, and with it Open CASCADE, only in the child process that reads
// the file (run_isolated), because Open CASCADE can crash on damaged files and its libraries
// take about 30 ms to load, which every other run of maxslice would pay. Its messages are
// captured instead of printed: syntax errors found by the STEP parser go into the refusal
// message.

#include <fmt/format.h>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <IMeshTools_Parameters.hxx>
#include <Interface_Check.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <mutex>
#include <numbers>
#include <string>
#include <vector>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

std::mutex& occt_mutex() {
    static std::mutex m;
    return m;
}

// Collects what Open CASCADE would print.
class CollectingPrinter : public Message_Printer {
public:
    std::vector<std::string> lines;

protected:
    void send(const TCollection_AsciiString& text, const Message_Gravity) const override {
        auto& self = const_cast<CollectingPrinter&>(*this);
        if (self.lines.size() < 1000) self.lines.emplace_back(text.ToCString());
    }
};

// Replaces the default messenger's printers while a file is read.
class CapturedMessages {
public:
    CapturedMessages() : printer_(new CollectingPrinter) {
        const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
        saved_ = messenger->Printers();
        messenger->ChangePrinters().Clear();
        printer_->SetTraceLevel(Message_Trace);
        messenger->AddPrinter(printer_);
    }
    CapturedMessages(const CapturedMessages&) = delete;
    CapturedMessages& operator=(const CapturedMessages&) = delete;
    ~CapturedMessages() {
        const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
        messenger->ChangePrinters().Clear();
        messenger->ChangePrinters().Append(saved_);
    }
    [[nodiscard]] const std::vector<std::string>& lines() const { return printer_->lines; }

private:
    Handle(CollectingPrinter) printer_;
    Message_SequenceOfPrinters saved_;
};

std::string trim(std::string s) {
    const auto not_decoration = [](char c) {
        return c != ' ' && c != '*' && c != '\t' && c != '\n' && c != '\r';
    };
    const auto first = std::find_if(s.begin(), s.end(), not_decoration);
    const auto last = std::find_if(s.rbegin(), s.rend(), not_decoration).base();
    return first < last ? std::string(first, last) : std::string();
}

// "Undefined Parsing: Line 22: Incorrect syntax: unexpected TYPE, ..." -> "line 22: ...".
std::string clean_syntax_message(std::string text) {
    text = trim(std::move(text));
    for (const std::string_view prefix : {"ERR StepFile : ", "Undefined Parsing: "}) {
        if (const auto at = text.find(prefix); at != std::string::npos) {
            text.erase(0, at + prefix.size());
        }
    }
    if (text.rfind("Line ", 0) == 0) text[0] = 'l';
    return text;
}

struct SyntaxReport {
    std::vector<std::string> syntax;  // parse errors
    std::size_t unresolved = 0;       // references to entities that do not exist
    std::string first_unresolved;

    [[nodiscard]] bool any() const { return !syntax.empty() || unresolved > 0; }
    [[nodiscard]] std::string describe() const {
        std::string s;
        if (!syntax.empty()) {
            s = fmt::format("{} syntax error{} (first: {})", syntax.size(),
                            syntax.size() == 1 ? "" : "s", syntax.front());
        }
        if (unresolved > 0) {
            if (!s.empty()) s += " and ";
            s += fmt::format("{} reference{} to missing entities (first: {})", unresolved,
                             unresolved == 1 ? "" : "s", first_unresolved);
        }
        return s;
    }
};

SyntaxReport syntax_report(const Handle(Interface_InterfaceModel) & model) {
    SyntaxReport report;
    if (model.IsNull()) return report;
    const Handle(Interface_Check)& check = model->GlobalCheck();
    if (check.IsNull()) return report;
    for (Standard_Integer i = 1; i <= check->NbFails(); ++i) {
        const std::string text = check->CFail(i);
        if (text.find("Unresolved Reference") != std::string::npos) {
            if (report.unresolved++ == 0) {
                // "Unresolved Reference, Ent.Id.#9063 Param.n0 3 (Id.#43)" -> "#43"
                const auto at = text.rfind("(Id.");
                const auto end = at == std::string::npos ? at : text.find(')', at);
                report.first_unresolved =
                    end != std::string::npos ? text.substr(at + 4, end - at - 4) : trim(text);
            }
        } else if (text.find("syntax") != std::string::npos ||
                   text.find("Parsing") != std::string::npos) {
            report.syntax.push_back(clean_syntax_message(text));
        }
    }
    return report;
}

std::optional<core::LengthUnit> unit_from_name(std::string name) {
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (name == "millimetre" || name == "millimeter") return core::LengthUnit::kMillimetre;
    return core::parse_unit(name);
}

// The declared length unit of a STEP file: one name if every shape representation agrees.
void step_units(STEPControl_Reader& reader, RawImport& out) {
    TColStd_SequenceOfAsciiString lengths, angles, solid_angles;
    reader.FileUnits(lengths, angles, solid_angles);
    std::vector<std::string> names;
    for (Standard_Integer i = 1; i <= lengths.Length(); ++i) {
        std::string n = lengths(i).ToCString();
        if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    }
    std::vector<core::LengthUnit> units;
    for (const std::string& n : names) {
        const auto u = unit_from_name(n);
        if (!u) {
            units.clear();
            break;
        }
        if (std::find(units.begin(), units.end(), *u) == units.end()) units.push_back(*u);
    }
    for (const std::string& n : names) {
        if (!out.declared_unit_text.empty()) out.declared_unit_text += ",";
        out.declared_unit_text += n;
    }
    if (units.size() == 1 && names.size() >= 1) out.declared_unit = units.front();
}

void iges_units(IGESControl_Reader& reader, RawImport& out) {
    const Handle(IGESData_IGESModel) model = Handle(IGESData_IGESModel)::DownCast(reader.Model());
    if (model.IsNull()) return;
    const IGESData_GlobalSection& global = model->GlobalSection();
    switch (global.UnitFlag()) {
        case 1: out.declared_unit = core::LengthUnit::kInch; break;
        case 2: out.declared_unit = core::LengthUnit::kMillimetre; break;
        case 4: out.declared_unit = core::LengthUnit::kFoot; break;
        case 6: out.declared_unit = core::LengthUnit::kMetre; break;
        case 9: out.declared_unit = core::LengthUnit::kMicron; break;
        case 10: out.declared_unit = core::LengthUnit::kCentimetre; break;
        default: break;
    }
    const Handle(TCollection_HAsciiString) name = global.UnitName();
    out.declared_unit_text = name.IsNull() ? std::string() : std::string(name->ToCString());
}

// The file's text contains AP242 tessellated geometry, which Open CASCADE 7.6 cannot read.
bool has_tessellated_geometry(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return text.find("TESSELLATED_SOLID") != std::string::npos ||
           text.find("TESSELLATED_SHELL") != std::string::npos ||
           text.find("TRIANGULATED_FACE") != std::string::npos;
}

std::unexpected<core::Error> invalid(std::string message) {
    return core::fail(core::ErrorCode::kInvalidInput, std::move(message));
}

struct Counts {
    std::size_t solids = 0;
    std::size_t shells_outside_solids = 0;
    std::size_t faces_outside_shells = 0;
    std::size_t faces = 0;
    std::size_t shells = 0;
};

Counts count_shapes(const TopoDS_Shape& shape) {
    Counts c;
    for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next()) ++c.solids;
    for (TopExp_Explorer e(shape, TopAbs_SHELL, TopAbs_SOLID); e.More(); e.Next()) {
        ++c.shells_outside_solids;
    }
    for (TopExp_Explorer e(shape, TopAbs_FACE, TopAbs_SHELL); e.More(); e.Next()) {
        ++c.faces_outside_shells;
    }
    for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) ++c.faces;
    for (TopExp_Explorer e(shape, TopAbs_SHELL); e.More(); e.Next()) ++c.shells;
    return c;
}

// Triangles of every solid, each solid checked for a positive volume.
core::Result<void> tessellate(const TopoDS_Shape& shape, const ImportOptions& options,
                              std::vector<double>& xyz, RawImport& out) {
    TopoDS_Compound solids;
    BRep_Builder builder;
    builder.MakeCompound(solids);
    for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next())
        builder.Add(solids, e.Current());

    IMeshTools_Parameters params;
    params.Deflection = options.chord_deviation_mm;
    params.Angle = options.angular_deviation_deg * std::numbers::pi / 180.0;
    params.Relative = Standard_False;
    params.InParallel = Standard_False;
    BRepMesh_IncrementalMesh mesher(solids, params);
    if (!mesher.IsDone()) return invalid("Open CASCADE could not tessellate the solids");

    std::size_t untessellated = 0;
    std::size_t internal_faces = 0;
    std::size_t inside_out = 0;
    std::size_t index = 0;
    for (TopExp_Explorer s(solids, TopAbs_SOLID); s.More(); s.Next(), ++index) {
        const std::size_t begin = xyz.size();
        for (TopExp_Explorer f(s.Current(), TopAbs_FACE); f.More(); f.Next()) {
            const TopoDS_Face& face = TopoDS::Face(f.Current());
            const TopAbs_Orientation orientation = face.Orientation();
            if (orientation != TopAbs_FORWARD && orientation != TopAbs_REVERSED) {
                ++internal_faces;  // internal/external faces do not bound the solid
                continue;
            }
            TopLoc_Location location;
            const Handle(Poly_Triangulation)& tri = BRep_Tool::Triangulation(face, location);
            if (tri.IsNull() || tri->NbTriangles() == 0) {
                ++untessellated;
                continue;
            }
            const gp_Trsf trsf = location.Transformation();
            const bool moved = !location.IsIdentity();
            // A mirroring placement (negative determinant) turns the winding too.
            const bool reversed = (orientation == TopAbs_REVERSED) != (moved && trsf.IsNegative());
            const Standard_Integer nodes = tri->NbNodes();
            for (Standard_Integer t = 1; t <= tri->NbTriangles(); ++t) {
                Standard_Integer n[3];
                tri->Triangle(t).Get(n[0], n[1], n[2]);
                if (reversed) std::swap(n[1], n[2]);
                for (const Standard_Integer k : n) {
                    if (k < 1 || k > nodes) return invalid("Open CASCADE made a bad triangulation");
                    gp_Pnt p = tri->Node(k);
                    if (moved) p.Transform(trsf);
                    xyz.insert(xyz.end(), {p.X(), p.Y(), p.Z()});
                }
            }
        }
        // A solid bounds a positive volume; a negative one means its shell came out
        // inside-out, and the whole solid is turned around.
        double six_v = 0.0;
        for (std::size_t i = begin; i + 9 <= xyz.size(); i += 9) {
            const double* c = xyz.data() + i;
            six_v += c[0] * (c[4] * c[8] - c[5] * c[7]) - c[1] * (c[3] * c[8] - c[5] * c[6]) +
                     c[2] * (c[3] * c[7] - c[4] * c[6]);
        }
        if (six_v < 0.0) {
            ++inside_out;
            for (std::size_t i = begin; i + 9 <= xyz.size(); i += 9) {
                std::swap_ranges(xyz.begin() + static_cast<std::ptrdiff_t>(i + 3),
                                 xyz.begin() + static_cast<std::ptrdiff_t>(i + 6),
                                 xyz.begin() + static_cast<std::ptrdiff_t>(i + 6));
            }
        }
    }
    if (untessellated > 0) {
        out.warnings.push_back(
            fmt::format("{} could not be tessellated; the mesh has holes where they were",
                        count_of(untessellated, "face")));
    }
    if (internal_faces > 0) {
        out.warnings.push_back(
            fmt::format("ignored {} inside solids", count_of(internal_faces, "internal face")));
    }
    if (inside_out > 0) {
        out.warnings.push_back(fmt::format("{} inside-out (negative volume) and turned around",
                                           count_of(inside_out, "solid was", "solids were")));
    }
    return {};
}

// Renumbers the vertices used by triangles (in their order) and drops the rest.
void drop_unused_vertices(mesh::TriangleMesh& m) {
    constexpr std::uint32_t kUnused = UINT32_MAX;
    std::vector<std::uint32_t> remap(m.vertices.size(), kUnused);
    std::vector<core::Vec3d> kept;
    kept.reserve(m.vertices.size());
    for (mesh::Triangle& t : m.triangles) {
        for (std::uint32_t& v : t) {
            if (remap[v] == kUnused) {
                remap[v] = static_cast<std::uint32_t>(kept.size());
                kept.push_back(m.vertices[v]);
            }
            v = remap[v];
        }
    }
    m.vertices = std::move(kept);
}

core::Result<RawImport> read_impl(const std::filesystem::path& path, Format format,
                                  const ImportOptions& options) {
    const std::string kind = format == Format::kStep ? "STEP" : "IGES";
    std::lock_guard lock(occt_mutex());
    CapturedMessages messages;

    RawImport out;
    out.format = format;
    out.converted_to_mm = true;

    std::unique_ptr<XSControl_Reader> reader;
    if (format == Format::kStep) {
        reader = std::make_unique<STEPControl_Reader>();
    } else {
        reader = std::make_unique<IGESControl_Reader>();
    }
    // Readers register the parameter when constructed; shapes must come out in mm.
    if (const char* unit = Interface_Static::CVal("xstep.cascade.unit");
        unit != nullptr && std::string_view(unit) != "MM") {
        Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    }

    const IFSelect_ReturnStatus status = reader->ReadFile(path.c_str());
    if (status != IFSelect_RetDone) {
        std::string why;
        for (const std::string& line : messages.lines()) {
            if (line.find("syntax") != std::string::npos || line.find("ERR") != std::string::npos) {
                why = clean_syntax_message(line);
                break;
            }
        }
        return invalid(
            fmt::format("not a readable {} file{}{}", kind, why.empty() ? "" : ": ", why));
    }
    const SyntaxReport syntax = syntax_report(reader->Model());

    if (format == Format::kStep) {
        step_units(static_cast<STEPControl_Reader&>(*reader), out);
    } else {
        iges_units(static_cast<IGESControl_Reader&>(*reader), out);
    }

    reader->TransferRoots();
    const TopoDS_Shape shape = reader->NbShapes() > 0 ? reader->OneShape() : TopoDS_Shape();
    const Counts counts = shape.IsNull() ? Counts{} : count_shapes(shape);
    const std::string also =
        syntax.any() ? fmt::format("; the file also has {}", syntax.describe()) : std::string();
    if (counts.solids == 0) {
        if (counts.faces > 0) {
            return invalid(fmt::format(
                "no solid: the {} file holds {} faces in {} shells but no closed solid; "
                "maxslice slices solids only: export the part as a solid body, or sew its "
                "surfaces into a closed solid in CAD{}",
                kind, counts.faces, counts.shells, also));
        }
        if (syntax.any()) {
            return invalid(fmt::format("damaged {} file: {}; no solid could be read", kind,
                                       syntax.describe()));
        }
        if (format == Format::kStep && has_tessellated_geometry(path)) {
            return invalid(
                "no solid: the STEP file holds only tessellated geometry (AP242 "
                "TESSELLATED_SOLID/TRIANGULATED_FACE), which Open CASCADE 7.6 does not read; "
                "export the part as a B-rep solid, or as STL/3MF");
        }
        return invalid(fmt::format("no solid: the {} file holds no solid, shell or face", kind));
    }
    if (syntax.any()) {
        return invalid(
            fmt::format("damaged {} file: {}; it is refused rather than read in "
                        "part: repair or export it again",
                        kind, syntax.describe()));
    }
    if (counts.shells_outside_solids > 0 || counts.faces_outside_shells > 0) {
        out.warnings.push_back(
            fmt::format("ignored {} and {} that are not part of a solid (only solids are read)",
                        count_of(counts.shells_outside_solids, "shell"),
                        count_of(counts.faces_outside_shells, "loose face")));
    }

    std::vector<double> xyz;
    if (auto ok = tessellate(shape, options, xyz, out); !ok) return std::unexpected(ok.error());
    if (xyz.empty()) {
        return invalid(
            fmt::format("the {} solids gave no triangles when tessellated", counts.solids));
    }
    out.solids = counts.solids;
    out.mesh = mesh::weld_exact(std::span<const double>(xyz));
    // Triangles that collapse onto two points once welded (BRepMesh puts several nodes on a
    // degenerated edge: the apex of a cone, the pole of a sphere) cover nothing, but their
    // doubled edge reads as non-manifold and misoriented; they are tessellation artefacts,
    // not part of the file, and are dropped.
    const std::size_t collapsed = std::erase_if(out.mesh.triangles, [](const mesh::Triangle& t) {
        return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
    });
    if (collapsed > 0) drop_unused_vertices(out.mesh);
    return out;
}

}  // namespace

namespace {

core::Result<RawImport> read_cad_in_process(const std::filesystem::path& path, Format format,
                                            const ImportOptions& options) {
    try {
        return read_impl(path, format, options);
    } catch (const Standard_Failure& failure) {
        const char* what = failure.GetMessageString();
        return invalid(fmt::format("Open CASCADE failed to read the file: {} ({})",
                                   (what != nullptr && *what != '\0') ? what : "no message",
                                   failure.DynamicType()->Name()));
    } catch (const std::bad_alloc&) {
        return invalid("not enough memory to read the file");
    } catch (const std::exception& e) {
        return invalid(fmt::format("Open CASCADE failed to read the file: {}", e.what()));
    } catch (...) {
        return invalid("Open CASCADE failed to read the file");
    }
}

}  // namespace

}  // namespace maxslice::io::detail

// The module's one entry point (loaded by cad_plugin.cpp): everything else in this module is
// hidden.
extern "C" __attribute__((visibility("default"))) void maxslice_read_cad_v1(
    const std::filesystem::path* path, maxslice::io::Format format,
    const maxslice::io::ImportOptions* options,
    maxslice::core::Result<maxslice::io::detail::RawImport>* out) {
    *out = maxslice::io::detail::read_cad_in_process(*path, format, *options);
}
