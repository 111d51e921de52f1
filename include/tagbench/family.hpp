#pragma once
// <tagbench/family.hpp>: tag families (the codebooks), decoding a code, and the printed layout of
// a tag for rendering it.
//
//   tagbench::builtin_family_names()      names of the shipped families ("36h11", "16h5", ...)
//   tagbench::load_family(name_or_path)   a built-in family, or a family file (.fam; the shipped ones
//                                         are installed in PREFIX/share/tagbench/families)
//   tagbench::TagFamily                   codes(), payload_width() d, min_hamming() h, decode(code, k)
//   tagbench::tag_cells(family, id)       the (d+4) x (d+4) cells of the printed tag, 1 = white
//
// Conventions: codes in AprilTag 1 bit order: the most significant bit is the top-left payload
// cell, row-major, 1 = white. A printed tag is (d+4) x (d+4) cells: a white ring, a black ring, the
// d x d payload; its "tag size" (for poses) is the black square's edge, d + 2 cells. decode()
// reports the rotation r with observed == rotate90^r(code) (clockwise quarter turns as printed).
//
// Thread safety: TagFamily is immutable after construction (decode is const); built-in families
// are built once on first use, thread-safely, then shared. Errors: std::invalid_argument (unknown
// family, bad family file) and std::out_of_range (tag_cells with an id out of range), one line each.
#include <tagbench/detail/codes/bits.hpp>
#include <tagbench/detail/codes/families.hpp>
#include <tagbench/detail/codes/tag_family.hpp>
#include <tagbench/detail/codes/tag_layout.hpp>
#include <tagbench/version.hpp>
