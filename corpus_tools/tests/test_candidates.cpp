// Candidate quads and their payloads (issue 5, section 2) on a tiny corpus made here
// (candidate_corpus.hpp): the tag's quad must be among the candidates with its code as bits; the store
// must round-trip and refuse damage with one line; scoring must equal TagFamily::decode record by
// record; the extraction must not depend on its thread count; shards must merge into the single run.
// The `tagbench corpus candidates|score|list` runs are in cli/tests/test_cli_candidates.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "candidates.hpp"
#include "sources.hpp"
#include "tests/candidate_corpus.hpp"
#include "tools/atomic_file.hpp"

namespace test_candidates {

namespace fs = std::filesystem;
using namespace tagbench;
using namespace tagbench::corpus;
using namespace tagbench::corpus::testing;

TEST(Candidates, RenderedTagIsAmongTheCandidatesWithItsCode) {
  std::size_t quads = 0;
  const auto recs = image_candidates(load("tag.png"), 3, DetectorOptions::paper(), &quads);
  ASSERT_GT(quads, 0u);
  const TagFamily& f = builtin_family("36h11");
  const Code code = f.codes()[kTagId];
  bool found = false;
  for (const auto& r : recs) {
    EXPECT_EQ(r.image, 3u);
    ASSERT_TRUE(r.d == 4 || r.d == 5 || r.d == 6);
    if (r.d != 6) continue;
    bool is_code = false;
    Code c = code;
    for (int k = 0; k < 4; ++k, c = rotate90(c, 6)) is_code = is_code || r.bits == c;
    if (!is_code) continue;
    // Its corners are the tag's (in some cyclic order), to a pixel.
    bool corners_match = false;
    for (int s = 0; s < 4; ++s) {
      double worst = 0;
      for (int i = 0; i < 4; ++i) {
        const auto& q = r.corners[static_cast<std::size_t>((i + s) % 4)];
        worst = std::max(worst, (Eigen::Vector2d(q[0], q[1]) - kTagCorners[static_cast<std::size_t>(i)]).norm());
      }
      corners_match = corners_match || worst < 1.0;
    }
    EXPECT_TRUE(corners_match);
    EXPECT_GT(r.margin, 0.5f);
    found = true;
  }
  EXPECT_TRUE(found);
  // Every quad gets at most one record per width, in quad order.
  EXPECT_LE(recs.size(), 3 * quads);
}

TEST(Candidates, BlankImageHasNone) {
  std::size_t quads = 99;
  EXPECT_TRUE(image_candidates(load("blank.png"), 0, DetectorOptions::paper(), &quads).empty());
  EXPECT_EQ(quads, 0u);
}

TEST(Candidates, CorpusImagesFromScanAndManifest) {
  const auto imgs = corpus_images(corpus_dir());
  ASSERT_EQ(imgs.size(), 6u);  // 5 images + the broken file, sorted by path
  EXPECT_EQ(imgs[0].file, "blank.png");
  EXPECT_EQ(imgs[1].file, "broken.jpg");
  EXPECT_EQ(imgs[1].status, "unreadable");
  EXPECT_EQ(imgs[3].file, "sub/rects0.png");
  EXPECT_EQ(imgs[5].file, "tag.png");
  const auto& s = store1();
  ASSERT_EQ(s.images.size(), 6u);
  EXPECT_EQ(s.images[5].width, 300);
  EXPECT_EQ(s.images[5].height, 220);
  EXPECT_EQ(s.images[0].quads, 0u);
  EXPECT_GT(s.images[3].quads + s.images[4].quads, 5u);  // rectangles make quads
  std::uint64_t q = 0;
  for (const auto& i : s.images) q += i.quads;
  EXPECT_EQ(q, s.quads);
  for (std::size_t i = 1; i < s.records.size(); ++i) EXPECT_LE(s.records[i - 1].image, s.records[i].image);
}

TEST(Candidates, StoreRoundTripAndJobsIndependence) {
  const auto& s = store1();
  ASSERT_FALSE(s.records.empty());
  const fs::path bin = corpus_dir() / "out" / "c.bin";
  fs::create_directories(bin.parent_path());
  write_candidates(bin, s);
  EXPECT_TRUE(fs::exists(corpus_dir() / "out" / "c.tsv"));
  const auto r = read_candidates(bin);
  EXPECT_EQ(r.settings, s.settings);
  EXPECT_EQ(r.quads, s.quads);
  EXPECT_EQ(r.images, s.images);
  EXPECT_EQ(r.records, s.records);
  EXPECT_EQ(r.settings, candidate_settings(DetectorOptions::paper()));
  // Two workers give the same bytes.
  const auto s2 = extract_candidates(corpus_dir(), corpus_images(corpus_dir()), DetectorOptions::paper(), 2);
  EXPECT_EQ(encode_candidates(s2), encode_candidates(s));
  EXPECT_EQ(candidate_index_tsv(s2.images), candidate_index_tsv(s.images));
}

TEST(Candidates, DamagedStoresAreRefusedWithOneLine) {
  const std::string good = encode_candidates(store1());
  const std::size_t rec0 = good.size() - store1().records.size() * 52;  // first record's offset
  std::vector<std::pair<std::string, std::string>> bad = {
      {"empty", ""},
      {"short header", good.substr(0, 20)},
      {"truncated by one byte", good.substr(0, good.size() - 1)},
      {"half a record missing", good.substr(0, good.size() - 26)},
      {"one byte too many", good + "x"},
  };
  auto flip = [&](std::size_t at, const std::string& what) {
    std::string b = good;
    b[at] = static_cast<char>(b[at] ^ 0x10);
    bad.emplace_back(what, b);
  };
  flip(0, "magic");
  flip(8, "version");
  flip(12, "record size");
  flip(40, "record count");
  // The header is outside the checksum: 2^28 more images must be refused (kMaxCandidateImages),
  // not allocated (fuzz finding: a damaged count asked for hundreds of GB).
  flip(19, "image count");
  flip(rec0 + 9, "record bits");
  flip(good.size() - 3, "last corner");
  flip(rec0 - 2, "settings text");
  for (const auto& [what, bytes] : bad) {
    try {
      decode_candidates(bytes, "x.bin");
      ADD_FAILURE() << what << " was accepted";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("x.bin: ", 0), 0u) << what << ": " << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << what;
    }
  }
  EXPECT_NO_THROW(decode_candidates(good, "x.bin"));
}

TEST(Candidates, ScoreEqualsDecodeRecordByRecord) {
  const auto& recs = store1().records;
  for (const std::string name : {"36h11", "25h9", "16h5"}) {
    const TagFamily& f = builtin_family(name);
    const int K = f.min_hamming() + 1;  // beyond (h-1)/2 too: nearest-code semantics
    const auto s = score_family(recs, f, K, 3);
    ASSERT_EQ(s.accepted.size(), static_cast<std::size_t>(K + 1));
    std::uint64_t quads = 0;
    for (const auto& r : recs) quads += r.d == f.payload_width();
    EXPECT_EQ(s.quads, quads) << name;
    EXPECT_GT(quads, 0u) << name;
    for (int k = 0; k <= K; ++k) {
      std::uint64_t n = 0;
      for (const auto& r : recs) n += r.d == f.payload_width() && f.decode(r.bits, k).has_value();
      EXPECT_EQ(s.accepted[static_cast<std::size_t>(k)], n) << name << " k=" << k;
      if (k > 0 && 2 * k < f.min_hamming()) {
        EXPECT_GE(s.accepted[static_cast<std::size_t>(k)], s.accepted[static_cast<std::size_t>(k - 1)]);
      }
    }
    EXPECT_LE(s.accepted.back(), s.quads);
  }
  // The rendered tag is accepted by 36h11 without correction.
  EXPECT_GE(score_family(recs, builtin_family("36h11"), 0).accepted[0], 1u);
  EXPECT_THROW(score_family(recs, builtin_family("16h5"), 17), std::invalid_argument);
}

TEST(Candidates, ListingDoesNotDecodeAndFilesThatDoNotDecodeAreUnreadableRows) {
  const fs::path d = side_dir("listing");
  fs::copy_file(corpus_dir() / "tag.png", d / "tag.png", fs::copy_options::overwrite_existing);
  const std::string bytes = slurp(d / "tag.png");
  std::ofstream(d / "cut.png", std::ios::binary) << bytes.substr(0, bytes.size() / 3);  // signature intact
  std::ofstream(d / "fake.png", std::ios::binary) << "no image signature";
  std::ofstream(d / "readme.txt") << "not an image";
  const auto imgs = corpus_images(d);
  ASSERT_EQ(imgs.size(), 3u);
  // Listed by signature only: the cut PNG is not found out yet, and no size is known before decoding.
  EXPECT_EQ(imgs[0].file, "cut.png");
  EXPECT_EQ(imgs[0].status, "ok");
  EXPECT_EQ(imgs[1].file, "fake.png");
  EXPECT_EQ(imgs[1].status, "unreadable");
  EXPECT_EQ(imgs[1].reason, "not decodable as an image");
  EXPECT_EQ(imgs[2].file, "tag.png");
  EXPECT_EQ(imgs[2].width, 0);
  // The extraction decodes each image once: sizes filled in, the cut file an unreadable row.
  const auto st = extract_candidates(d, imgs, DetectorOptions::paper(), 2);
  ASSERT_EQ(st.images.size(), 3u);
  EXPECT_EQ(st.images[0].status, "unreadable");
  EXPECT_FALSE(st.images[0].reason.empty());
  EXPECT_EQ(st.images[1].status, "unreadable");
  EXPECT_EQ(st.images[2].status, "ok");
  EXPECT_EQ(st.images[2].width, 300);
  EXPECT_EQ(st.images[2].height, 220);
  // `corpus list` still decodes: the cut file is unreadable there, the good one has its size.
}

// ---- Shards (issue 5, section 4) ----

TEST(CandidateShards, ParseShard) {
  EXPECT_EQ(parse_shard("0/1"), (Shard{0, 1}));
  EXPECT_EQ(parse_shard("2/3"), (Shard{2, 3}));
  EXPECT_EQ(parse_shard("17/100"), (Shard{17, 100}));
  const auto error = [](const std::string& text) {
    try {
      parse_shard(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  for (const std::string bad : {"3/3", "-1/2", "1/0", "0/0", "x/y", "1", "1/", "/2", "1/2/3", "+1/2", "1 /2", "",
                                "1/2x", "99999999999999999999/2"}) {
    const std::string m = error(bad);
    EXPECT_EQ(m.rfind("'" + bad + "': ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  EXPECT_EQ(error("3/3"), "'3/3': i must be below N (shards are numbered 0 to N-1)");
  EXPECT_EQ(error("1/0"), "'1/0': N must be at least 1");
  EXPECT_EQ(error("x/y"), "'x/y': not of the form i/N (shard i of N, counted from 0)");
}

TEST(CandidateShards, RangesAreContiguousBalancedAndCoverTheList) {
  EXPECT_EQ(shard_range(6, {0, 3}), (std::pair<std::size_t, std::size_t>{0, 2}));
  EXPECT_EQ(shard_range(6, {2, 3}), (std::pair<std::size_t, std::size_t>{4, 6}));
  EXPECT_EQ(shard_range(5, {0, 3}), (std::pair<std::size_t, std::size_t>{0, 1}));  // floor(i*M/N)
  EXPECT_EQ(shard_range(5, {1, 3}), (std::pair<std::size_t, std::size_t>{1, 3}));
  EXPECT_EQ(shard_range(2, {0, 5}), (std::pair<std::size_t, std::size_t>{0, 0}));  // more shards than images
  EXPECT_EQ(shard_range(0, {0, 1}), (std::pair<std::size_t, std::size_t>{0, 0}));
  for (std::size_t m : {0u, 1u, 5u, 6u, 97u, 1000u})
    for (std::uint64_t n : {1u, 2u, 3u, 7u, 64u, 1001u}) {
      std::size_t next = 0;
      for (std::uint64_t i = 0; i < n; ++i) {
        const auto [b, e] = shard_range(m, {i, n});
        ASSERT_EQ(b, next) << m << " " << i << "/" << n;
        ASSERT_LE(e - b, (m + n - 1) / n) << m << " " << i << "/" << n;
        ASSERT_GE(e - b, m / n) << m << " " << i << "/" << n;
        next = e;
      }
      EXPECT_EQ(next, m) << m << " /" << n;
    }
  // i * M overflows 64 bits here; the edges must still be exact.
  const std::uint64_t big = std::numeric_limits<std::uint64_t>::max();
  EXPECT_EQ(shard_range(10, {big - 1, big}), (std::pair<std::size_t, std::size_t>{9, 10}));
  EXPECT_EQ(shard_range(10, {big / 2, big}), (std::pair<std::size_t, std::size_t>{4, 5}));
  EXPECT_THROW(shard_range(6, {3, 3}), std::invalid_argument);
  EXPECT_THROW(shard_range(6, {0, 0}), std::invalid_argument);
}

TEST(CandidateShards, SettingsLinesRoundTrip) {
  const ShardInfo info{{2, 5}, 7, 19, 0x0123456789abcdefULL, 0xfedcba9876543210ULL};
  const std::string base = candidate_settings(DetectorOptions::paper());
  const std::string lines = shard_settings_lines(info);
  EXPECT_EQ(lines,
            "shard=2/5\nshard_first_row=7\ncorpus_images=19\ncorpus_list_fnv1a=0123456789abcdef\n"
            "shard_list_fnv1a=fedcba9876543210\n");
  std::string detector;
  const auto back = parse_shard_settings(base + lines, "s.bin", &detector);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(*back, info);
  EXPECT_EQ(detector, base);
  EXPECT_FALSE(parse_shard_settings(base, "s.bin").has_value());  // an unsharded store
  const std::vector<std::string> malformed = {
      base + "shard=2/5\n",                                             // lines missing
      base + lines + "extra=1\n",                                       // a line too many
      base + "shard=5/5\n" + lines.substr(10),                          // i not below N
      base + lines.substr(0, lines.size() - 1),                         // no final newline
      base + "shard=2/5\nshard_first_row=x\n" + lines.substr(lines.find("corpus_images")),  // not a number
  };
  for (const std::string& bad : malformed) {
    try {
      parse_shard_settings(bad, "s.bin");
      ADD_FAILURE() << "accepted: " << bad.substr(base.size());
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("s.bin: malformed shard lines", 0), 0u) << e.what();
    }
  }
}

namespace {

// Shard i of n of the test corpus, written to and read back from files as `corpus candidates
// --shard` and `corpus merge` do, so the index goes through its .tsv.
CandidateStore shard_store(std::uint64_t i, std::uint64_t n, int jobs = 1) {
  const auto s = extract_candidate_shard(corpus_dir(), corpus_images(corpus_dir()), {i, n}, DetectorOptions::paper(), jobs);
  const fs::path bin = corpus_dir() / "shards" / (std::to_string(i) + "of" + std::to_string(n) + ".bin");
  fs::create_directories(bin.parent_path());
  write_candidates(bin, s);
  return read_candidates(bin);
}

std::vector<CandidateStore> all_shards(std::uint64_t n) {
  std::vector<CandidateStore> v;
  for (std::uint64_t i = 0; i < n; ++i) v.push_back(shard_store(i, n, 1 + static_cast<int>(i % 2)));
  return v;
}

// The one-line message merge_candidates throws, or "" if it accepted.
std::string merge_error(std::vector<CandidateStore> shards, const std::vector<std::string>& names) {
  try {
    merge_candidates(std::move(shards), names);
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CandidateShards, AShardHoldsItsBlockWithLocalIds) {
  const auto& whole = store1();  // 6 images: shard 1/3 is rows 2 and 3
  const auto s = shard_store(1, 3);
  ASSERT_EQ(s.images.size(), 2u);
  EXPECT_EQ(s.images[0], whole.images[2]);
  EXPECT_EQ(s.images[1], whole.images[3]);
  std::vector<CandidateRecord> expect;
  for (auto r : whole.records)
    if (r.image == 2 || r.image == 3) {
      r.image -= 2;
      expect.push_back(r);
    }
  ASSERT_FALSE(expect.empty());  // sub/rects0.png has quads
  EXPECT_EQ(s.records, expect);
  EXPECT_EQ(s.quads, whole.images[2].quads + whole.images[3].quads);
  std::string detector;
  const auto info = parse_shard_settings(s.settings, "s", &detector);
  ASSERT_TRUE(info.has_value());
  EXPECT_EQ(detector, whole.settings);
  EXPECT_EQ(info->shard, (Shard{1, 3}));
  EXPECT_EQ(info->first_row, 2u);
  EXPECT_EQ(info->corpus_images, 6u);
  EXPECT_EQ(info->corpus_list, image_list_hash(whole.images, 0, 6));
  EXPECT_EQ(info->shard_list, image_list_hash(whole.images, 2, 4));
  EXPECT_NE(info->shard_list, image_list_hash(whole.images, 1, 3));
}

TEST(CandidateShards, MergedShardsAreByteIdenticalToTheSingleRun) {
  const std::string bin = encode_candidates(store1()), tsv = candidate_index_tsv(store1().images);
  for (const std::uint64_t n : {1u, 2u, 3u, 4u, 8u}) {  // 8 > 6 images: shards 0 and 4 are empty
    auto shards = all_shards(n);
    std::reverse(shards.begin(), shards.end());  // the order given must not matter
    if (n == 8) {
      std::size_t empty = 0;
      for (const auto& s : shards) empty += s.images.empty();
      EXPECT_EQ(empty, 2u);
    }
    const auto m = merge_candidates(std::move(shards));
    EXPECT_EQ(encode_candidates(m), bin) << "N=" << n;
    EXPECT_EQ(candidate_index_tsv(m.images), tsv) << "N=" << n;
    EXPECT_EQ(m.images, store1().images) << "N=" << n;
  }
}

TEST(CandidateShards, MergeRefusesWhatDoesNotFit) {
  const auto good = all_shards(3);
  const std::vector<std::string> names = {"a.bin", "b.bin", "c.bin", "d.bin"};
  ASSERT_EQ(merge_error(good, names), "");

  // A shard missing, first gap named, wherever it is.
  EXPECT_NE(merge_error({good[0], good[2]}, names).find("shard 1/3 is missing: 2 of 3 shards given (a.bin, b.bin)"),
            std::string::npos)
      << merge_error({good[0], good[2]}, names);
  EXPECT_NE(merge_error({good[1], good[2]}, names).find("shard 0/3 is missing"), std::string::npos);
  EXPECT_NE(merge_error({good[0]}, names).find("shard 1/3 is missing (and 1 more)"), std::string::npos);
  // Duplicated, naming both files.
  EXPECT_EQ(merge_error({good[0], good[1], good[2], good[1]}, names), "d.bin: shard 1/3 is also given as b.bin");
  // Other detector settings, naming the line.
  {
    auto v = good;
    const auto at = v[2].settings.find("seg_sigma=");
    v[2].settings.replace(at, v[2].settings.find('\n', at) - at, "seg_sigma=1.5");
    const auto e = merge_error(v, names);
    EXPECT_EQ(e.rfind("c.bin: detector settings differ from a.bin's ('seg_sigma=1.5' against 'seg_sigma=0.8", 0), 0u)
        << e;
  }
  // Another N.
  {
    auto v = good;
    v[1] = shard_store(1, 4);
    EXPECT_EQ(merge_error(v, names).rfind("b.bin: shard 1/4, but a.bin is shard 0/3", 0), 0u) << merge_error(v, names);
  }
  // Another corpus list (a file added to the corpus between the shards' runs).
  {
    auto images = corpus_images(corpus_dir());
    CandidateImage extra = images[1];
    extra.file = "zzz_added.jpg";
    images.push_back(extra);  // unreadable, so nothing is decoded: only the list differs
    auto v = good;
    v[2] = extract_candidate_shard(corpus_dir(), images, {2, 3}, DetectorOptions::paper(), 1);
    const auto e = merge_error(v, names);
    EXPECT_EQ(e.rfind("c.bin: made from a corpus list of 7 images", 0), 0u) << e;
    EXPECT_NE(e.find("a.bin from one of 6"), std::string::npos) << e;
    EXPECT_NE(e.find("the corpus changed"), std::string::npos) << e;
    // The same count with another file is caught by the list's hash.
    images.erase(images.begin());  // blank.png gone: 6 again
    v[2] = extract_candidate_shard(corpus_dir(), images, {2, 3}, DetectorOptions::paper(), 1);
    EXPECT_EQ(merge_error(v, names).rfind("c.bin: made from a corpus list of 6 images", 0), 0u)
        << merge_error(v, names);
  }
  // An unsharded store.
  {
    auto v = good;
    v.push_back(store1());
    EXPECT_EQ(merge_error(v, names).rfind("d.bin: not a shard store", 0), 0u) << merge_error(v, names);
  }
  // An index that is not the shard's: another file name, one image fewer, a changed quad count.
  {
    auto v = good;
    v[1].images[0].file = "renamed.png";
    EXPECT_EQ(merge_error(v, names), "b.bin: its image index (.tsv) does not list the images the store was made from");
    v = good;
    v[1].images.pop_back();
    EXPECT_EQ(merge_error(v, names).rfind("b.bin: shard 1/3 of 6 images must hold rows 2 to 4", 0), 0u)
        << merge_error(v, names);
    v = good;
    v[1].images[0].quads += 1;
    EXPECT_EQ(merge_error(v, names).rfind("b.bin: its image index counts", 0), 0u) << merge_error(v, names);
  }
  // A shard line that claims another block (its hashes intact).
  {
    auto v = good;
    const auto at = v[1].settings.find("shard_first_row=2");
    ASSERT_NE(at, std::string::npos);
    v[1].settings.replace(at, 17, "shard_first_row=1");
    EXPECT_EQ(merge_error(v, names).rfind("b.bin: shard 1/3 of 6 images must hold rows 2 to 4", 0), 0u)
        << merge_error(v, names);
  }
  // Without names, stores are named by position.
  EXPECT_EQ(merge_error({good[0], good[0]}, {}), "shard store 2: shard 0/3 is also given as shard store 1");
  EXPECT_THROW(merge_candidates({}), std::runtime_error);
}

TEST(CandidateShards, ScannedListingSkipsTheStoresOwnFiles) {
  // A temporary store file that vanished between listing and opening would be an unreadable row
  // in one shard's list only; a garbage "corpus_candidates*" image file stands in for it here.
  const fs::path d = corpus_dir() / "own";
  fs::create_directories(d / "sub");
  cv::imwrite((d / "a.png").string(), cv::Mat(20, 30, CV_8UC1, cv::Scalar(60)));
  std::ofstream(d / "corpus_candidates-shard-0-of-2.png") << "vanished";
  std::ofstream(d / "sub" / "corpus_candidates.png") << "a user's file, deeper down";
  const auto imgs = corpus_images(d);
  ASSERT_EQ(imgs.size(), 2u);
  EXPECT_EQ(imgs[0].file, "a.png");
  EXPECT_EQ(imgs[1].file, "sub/corpus_candidates.png");
  EXPECT_EQ(imgs[1].status, "unreadable");
}

}  // namespace test_candidates
