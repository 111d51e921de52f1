// tagbench.Family, tagbench.family_names(), tagbench.render_tag(): the codebooks, decoding a code
// and a tag's printed layout as a numpy array (<tagbench/family.hpp>).
#include <cstdint>
#include <stdexcept>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include <tagbench/family.hpp>

namespace py = pybind11;

namespace tagbench::python {
namespace {

// The tag as an 8-bit gray array, `px_per_cell` pixels a cell, inside a white border of `margin`
// pixels: 0 = black, 255 = white, (d+4) * px_per_cell + 2 * margin pixels square.
py::array_t<std::uint8_t> render(const TagFamily& family, int id, int px_per_cell, int margin) {
  if (px_per_cell < 1 || px_per_cell > 1000)
    throw std::invalid_argument("px_per_cell = " + std::to_string(px_per_cell) + ": must be 1..1000");
  if (margin < 0 || margin > 100000)
    throw std::invalid_argument("margin = " + std::to_string(margin) + ": must be 0..100000");
  const TagCells cells = tag_cells(family, id);  // std::out_of_range (IndexError) for a bad id
  const py::ssize_t side = static_cast<py::ssize_t>(cells.n) * px_per_cell + 2 * margin;
  py::array_t<std::uint8_t> out({side, side});
  auto px = out.mutable_unchecked<2>();
  for (py::ssize_t y = 0; y < side; ++y)
    for (py::ssize_t x = 0; x < side; ++x) {
      const py::ssize_t cy = y - margin, cx = x - margin;
      const bool inside = cy >= 0 && cx >= 0 && cy < side - 2 * margin && cx < side - 2 * margin;
      px(y, x) = !inside || cells.at(static_cast<int>(cy / px_per_cell), static_cast<int>(cx / px_per_cell)) ? 255 : 0;
    }
  return out;
}

}  // namespace

void bind_families(py::module_& m) {
  m.def("family_names", &builtin_family_names, "Names of the built-in families, in display order.");

  py::class_<TagFamily>(m, "Family",
                        "A tag family: codes in AprilTag 1 bit order (MSB = top-left payload cell, row-major, "
                        "1 = white). Family(name_or_path): a built-in name ('36h11') or a .fam file.")
      .def(py::init([](const std::string& name) { return load_family(name); }), py::arg("name"))
      .def_property_readonly("name", &TagFamily::name)
      .def_property_readonly("bits", &TagFamily::bits)
      .def_property_readonly("payload_width", &TagFamily::payload_width, "d: the payload is d x d cells")
      .def_property_readonly("min_hamming", &TagFamily::min_hamming, "h: minimum distance over all rotations")
      .def_property_readonly("codes", &TagFamily::codes, "The codes as ints, index = id.")
      .def("__len__", &TagFamily::size)
      .def(
          "decode",
          [](const TagFamily& f, Code observed, int max_hamming) -> py::object {
            if (max_hamming < 0) throw std::invalid_argument("max_hamming = " + std::to_string(max_hamming) + ": must be >= 0");
            if (f.bits() < 64 && (observed >> f.bits()) != 0)  // a word of another family, or a mistake
              throw std::invalid_argument("code " + std::to_string(observed) + ": more than the family's " +
                                          std::to_string(f.bits()) + " bits");
            const auto r = f.decode(observed, max_hamming);
            if (!r) return py::none();
            return py::make_tuple(r->id, r->hamming, r->rotation);
          },
          py::arg("code"), py::arg("max_hamming") = 0,
          "(id, hamming, rotation) of the nearest code within max_hamming bits over all rotations, or None; "
          "observed == the code turned `rotation` clockwise quarter turns.")
      .def("render", &render, py::arg("id"), py::arg("px_per_cell") = 1, py::arg("margin") = 0,
           "The printed tag as a uint8 array (0 black, 255 white): (d+4) cells a side, px_per_cell pixels each, "
           "inside a white border of `margin` pixels. IndexError for an id out of range.")
      .def("__repr__", [](const TagFamily& f) {
        return "tagbench.Family('" + f.name() + "', " + std::to_string(f.size()) + " codes, h=" +
               std::to_string(f.min_hamming()) + ")";
      });

  m.def(
      "render_tag",
      [](const std::string& family, int id, int px_per_cell, int margin) {
        return render(load_family(family), id, px_per_cell, margin);
      },
      py::arg("family"), py::arg("id"), py::arg("px_per_cell") = 1, py::arg("margin") = 0,
      "Family(family).render(id, px_per_cell, margin).");
}

}  // namespace tagbench::python
