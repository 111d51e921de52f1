#!/usr/bin/env bash
# The installed package, tested from an install of the already-built tree into a temporary prefix
# (ctest: examples/tests/CMakeLists.txt). Usage:
#   install_tests.sh STEP SOURCE_DIR BUILD_DIR PREFIX LIBDIR CXX PYTHON
# STEP: install | headers | find_package | pkg_config | python | example_python | readme
# Each step leaves its work in PREFIX.work/STEP; a failure prints one line naming what failed.
set -euo pipefail
step=$1 src=$2 build=$3 prefix=$4 libdir=$5 cxx=$6 python=$7
work=$prefix.work/$step
rm -rf "$work" && mkdir -p "$work"
# grep -q would stop reading at the first match and fail the pipeline (pipefail) with SIGPIPE.
quiet_grep() { grep "$@" >/dev/null; }
fail() { echo "install_tests $step: $*" >&2; exit 1; }
export PKG_CONFIG_PATH=$prefix/$libdir/pkgconfig
pyroot=$prefix/lib/python3/dist-packages

# The fenced block after the README's marker "<!-- quickstart: NAME -->", so what the README shows is
# what runs here.
quickstart() {
  awk -v name="$1" '
    $0 == "<!-- quickstart: " name " -->" { want = 1; next }
    want && /^```/ { if (inside) exit; inside = 1; next }
    inside { print }' "$src/README.md"
}

case $step in
install)
  rm -rf "$prefix"
  cmake --install "$build" --prefix "$prefix" >"$work/install.log"
  # What a user relies on (listing in README "Install").
  for f in bin/tagbench include/tagbench/detector.hpp include/tagbench/family.hpp include/tagbench/opencv.hpp \
           include/tagbench/version.hpp include/tagbench/tagbench.hpp include/tagbench/detail/detect/detector.hpp \
           "$libdir/libtagbench.a" "$libdir/libtagbench.so" "$libdir/cmake/tagbench/tagbench-config.cmake" \
           "$libdir/pkgconfig/tagbench.pc" "$libdir/pkgconfig/tagbench-opencv.pc" share/tagbench/families/tag36h11.fam; do
    [[ -e $prefix/$f ]] || fail "missing $f"
  done
  ls "$pyroot"/tagbench*.so >/dev/null 2>&1 || fail "missing the Python module in lib/python3/dist-packages"
  soname=$(objdump -p "$prefix/$libdir/libtagbench.so" | awk '$1 == "SONAME" { print $2 }')
  [[ $soname =~ ^libtagbench\.so\.[0-9]+(\.[0-9]+)?$ ]] || fail "SONAME '$soname'"
  [[ -e $prefix/$libdir/$soname ]] || fail "no $soname"
  # The installed program runs and knows the shipped families.
  "$prefix/bin/tagbench" family list | quiet_grep 36h11 || fail "tagbench family list"
  ;;
headers)
  # Every public header compiles alone from the install; only opencv.hpp needs OpenCV's headers.
  for h in detector family version tagbench; do
    printf '#include <tagbench/%s.hpp>\nint main() {}\n' "$h" >"$work/$h.cpp"
    "$cxx" -std=c++20 -Wall -Wextra -Werror -fsyntax-only $(pkg-config --cflags tagbench) "$work/$h.cpp" ||
      fail "<tagbench/$h.hpp> does not compile alone"
  done
  pkg-config --cflags tagbench | quiet_grep opencv && fail "tagbench.pc puts OpenCV on the include path"
  printf '#include <tagbench/opencv.hpp>\nint main() {}\n' >"$work/opencv.cpp"
  # OpenCV's own headers as system headers: OpenCV 4.6's mat.inl.hpp warns under C++20.
  "$cxx" -std=c++20 -Wall -Wextra -Werror -fsyntax-only $(pkg-config --cflags tagbench) \
      $(pkg-config --cflags-only-I opencv4 | sed 's/-I/-isystem /g') "$work/opencv.cpp" ||
    fail "<tagbench/opencv.hpp> does not compile alone"
  ;;
find_package)
  cmake -S "$src/examples/cpp_consumer" -B "$work" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" \
        -DCMAKE_BUILD_TYPE=Release >"$work.log" || { cat "$work.log"; fail "configure"; }
  cmake --build "$work" >>"$work.log" || { cat "$work.log"; fail "build"; }
  "$work/consumer" 36h11 7 && "$work/consumer" 16h5 29 || fail "consumer"
  "$work/consumer_static" 36h11 586 || fail "consumer_static"
  ldd "$work/consumer" | quiet_grep "$prefix/$libdir/libtagbench.so" || fail "consumer not linked with the installed libtagbench.so"
  ldd "$work/consumer_static" | quiet_grep libtagbench && fail "consumer_static linked with libtagbench.so"
  readelf -d "$work/consumer" | quiet_grep "NEEDED.*libopencv" && fail "consumer (shared) linked with OpenCV itself"
  ;;
pkg_config)
  # The build command written in consumer.cpp's header, as a user would type it.
  cmd=$(sed -n 's|^//   \(c++ -std=c++20 consumer.cpp .*\)$|\1|p' "$src/examples/cpp_consumer/consumer.cpp")
  [[ -n $cmd ]] || fail "no pkg-config command in consumer.cpp"
  cp "$src/examples/cpp_consumer/consumer.cpp" "$work/"
  (cd "$work" && eval "${cmd/#c++/\"$cxx\"}") || fail "build: $cmd"
  export LD_LIBRARY_PATH=$prefix/$libdir
  "$work/consumer" 36h11 7 && "$work/consumer" 25h9 34 || fail "consumer"
  ;;
python)
  PYTHONPATH=$pyroot TAGBENCH_EXPECT_MODULE_DIR=$pyroot "$python" "$src/python/tests/test_tagbench.py"
  ;;
example_python)
  "$prefix/bin/tagbench" render --family 36h11 --id 5 --px-per-cell 8 -o "$work/a.png"
  "$prefix/bin/tagbench" render --family 16h5 --id 2 --px-per-cell 8 -o "$work/b.png"
  PYTHONPATH=$pyroot "$python" "$src/examples/python/detect.py" --family 36h11 --family 16h5 \
      --camera 400,400,31.5,31.5 --tag-size 0.1 "$work/a.png" "$work/b.png" >"$work/out.json"
  "$python" - "$work/out.json" <<'PY' || fail "detect.py output"
import json, sys
doc = json.load(open(sys.argv[1]))
got = [(d["family"], d["id"]) for im in doc["images"] for d in im["detections"]]
assert got == [("36h11", 5), ("16h5", 2)], got
d = doc["images"][0]["detections"][0]
assert len(d["corners"]) == 4 and d["pose"] is not None and d["pose"]["t"][2] > 0, d
PY
  if PYTHONPATH=$pyroot "$python" "$src/examples/python/detect.py" "$work/missing.png" >"$work/bad.out" 2>"$work/bad.err"; then
    fail "detect.py accepted a missing file"
  fi
  [[ ! -s $work/bad.out && $(wc -l <"$work/bad.err") -eq 1 ]] || fail "detect.py: a bad input must give one line and no output"
  ;;
readme)
  # The README's quick starts, C++ (find_package and pkg-config) and Python, run as written.
  "$prefix/bin/tagbench" render --family 36h11 --id 7 --px-per-cell 10 -o "$work/tag.png"
  quickstart detect_tags.cpp >"$work/detect_tags.cpp"
  quickstart CMakeLists.txt >"$work/CMakeLists.txt"
  quickstart pkg-config >"$work/pkg-config.sh"
  quickstart detect.py >"$work/detect.py"
  for f in detect_tags.cpp CMakeLists.txt pkg-config.sh detect.py; do [[ -s $work/$f ]] || fail "README has no quickstart $f"; done
  cmake -S "$work" -B "$work/build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" >"$work/cmake.log" ||
    { cat "$work/cmake.log"; fail "C++ quick start (find_package): configure"; }
  cmake --build "$work/build" >>"$work/cmake.log" || { cat "$work/cmake.log"; fail "C++ quick start (find_package): build"; }
  out=$("$work/build/detect_tags" "$work/tag.png")
  echo "$out"; [[ $out == *"36h11 id 7 "* ]] || fail "C++ quick start (find_package) did not find 36h11 id 7"
  (cd "$work" && PATH=$(dirname "$cxx"):$PATH CXX=$cxx bash -e pkg-config.sh) || fail "C++ quick start (pkg-config): build"
  out=$(LD_LIBRARY_PATH=$prefix/$libdir "$work/detect_tags" "$work/tag.png")
  echo "$out"; [[ $out == *"36h11 id 7 "* ]] || fail "C++ quick start (pkg-config) did not find 36h11 id 7"
  out=$(cd "$work" && PYTHONPATH=$pyroot "$python" detect.py)
  echo "$out"; [[ $out == "36h11 7 "* ]] || fail "Python quick start did not print 36h11 7"
  ;;
deb)
  # What `make deb` makes (cpack in the build tree, here into $work), read back with dpkg-deb.
  cpack --config "$build/CPackConfig.cmake" -B "$work" >"$work/cpack.log" || { cat "$work/cpack.log"; fail "cpack"; }
  deb() { ls "$work"/"$1"_*.deb 2>/dev/null | head -1; }
  for p in tagbench libtagbench-dev python3-tagbench; do [[ -n $(deb $p) ]] || fail "no $p package"; done
  has() { dpkg-deb -c "$(deb "$1")" | awk '{ print $6 }' | quiet_grep -E "^\./usr/$2\$" || fail "$1 lacks /usr/$2"; }
  has tagbench bin/tagbench
  has tagbench "lib/(x86_64-linux-gnu/)?libtagbench\.so\.[0-9.]+"
  has tagbench share/tagbench/families/tag36h11.fam
  has libtagbench-dev include/tagbench/detector.hpp
  has libtagbench-dev include/tagbench/detail/detect/detector.hpp
  has libtagbench-dev "lib/(x86_64-linux-gnu/)?libtagbench\.(so|a)"
  has libtagbench-dev "lib/(x86_64-linux-gnu/)?cmake/tagbench/tagbench-config\.cmake"
  has libtagbench-dev "lib/(x86_64-linux-gnu/)?pkgconfig/tagbench\.pc"
  has python3-tagbench "lib/python3/dist-packages/tagbench\..*\.so"
  dpkg-deb -c "$(deb tagbench)" | quiet_grep include/ && fail "headers in the runtime package"
  # Together the packages hold exactly what cmake --install puts in a prefix (no file left without
  # a component, none twice).
  for p in tagbench libtagbench-dev python3-tagbench; do
    dpkg-deb -c "$(deb $p)" | awk '$1 !~ /^d/ { sub(/^\.\/usr\//, "", $6); print $6 }'
  done | sort >"$work/debs.txt"
  (cd "$prefix" && find . ! -type d | sed 's|^\./||' | sort) >"$work/prefix.txt"
  diff "$work/prefix.txt" "$work/debs.txt" >"$work/diff.txt" || { cat "$work/diff.txt"; fail "packages differ from the install"; }
  depends() { dpkg-deb -f "$(deb "$1")" Depends; }
  dpkg-deb -I "$(deb tagbench)" | quiet_grep "Package: tagbench" || fail "dpkg-deb -I tagbench"
  for d in libopencv-core libopencv-imgproc libc6; do depends tagbench | quiet_grep "$d" || fail "tagbench does not depend on $d"; done
  for d in "tagbench (= " libeigen3-dev libopencv-dev; do depends libtagbench-dev | quiet_grep -F "$d" || fail "libtagbench-dev does not depend on $d"; done
  for d in python3 python3-numpy; do depends python3-tagbench | quiet_grep -w "$d" || fail "python3-tagbench does not depend on $d"; done
  ;;
*) fail "unknown step" ;;
esac
echo "install_tests $step: ok"
