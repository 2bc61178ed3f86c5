// Writes a small seed corpus for each fuzz target into DIR/<target>/: valid inputs (a floor
// and a table top) in every layout the target reads, for the fuzzer to mutate.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

namespace {

pcl::PointCloud<pcl::PointXYZ> twoSheets() {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      cloud.push_back(pcl::PointXYZ(0.05f * i, 0.05f * j, 0.0f));
      if (i > 3 && j > 3) cloud.push_back(pcl::PointXYZ(0.05f * i, 0.05f * j, 0.3f));
    }
  return cloud;
}

template <class T>
void put(std::vector<std::uint8_t>& out, T value) {
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(&value);
  out.insert(out.end(), bytes, bytes + sizeof(T));
}

void save(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::uint8_t> fileWithPrefix(std::uint8_t prefix, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> bytes{prefix};
  bytes.insert(bytes.end(), std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_seeds DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  const pcl::PointCloud<pcl::PointXYZ> cloud = twoSheets();

  // PointCloud2: width, height, point_step, row_step, big-endian, fields (offset, type, count).
  for (std::uint32_t height : {1u, 4u}) {
    std::vector<std::uint8_t> seed;
    const std::uint32_t n = static_cast<std::uint32_t>(cloud.size()) / height * height;
    put(seed, n / height);
    put(seed, height);
    put(seed, std::uint32_t(16));
    put(seed, std::uint32_t(16 * (n / height)));
    put(seed, std::uint8_t(0));
    put(seed, std::uint8_t(3));
    for (std::uint32_t k = 0; k < 3; ++k) {
      put(seed, 4 * k);
      put(seed, std::uint8_t(7));  // FLOAT32
      put(seed, std::uint32_t(1));
    }
    for (std::uint32_t i = 0; i < n; ++i) {
      const float xyzw[4] = {cloud[i].x, cloud[i].y, cloud[i].z, 1.0f};
      for (float v : xyzw) put(seed, v);
    }
    save(dir + "/pointcloud2/seed_h" + std::to_string(height), seed);
  }

  // Cloud files: 0 + a PCD in each encoding, 1 + a PLY in each.
  pcl::PCDWriter pcd;
  pcd.writeASCII(dir + "/tmp.pcd", cloud);
  save(dir + "/cloud_file/ascii_pcd", fileWithPrefix(0, dir + "/tmp.pcd"));
  pcd.writeBinary(dir + "/tmp.pcd", cloud);
  save(dir + "/cloud_file/binary_pcd", fileWithPrefix(0, dir + "/tmp.pcd"));
  pcd.writeBinaryCompressed(dir + "/tmp.pcd", cloud);
  save(dir + "/cloud_file/compressed_pcd", fileWithPrefix(0, dir + "/tmp.pcd"));
  pcl::PLYWriter ply;
  ply.write(dir + "/tmp.ply", cloud, false);
  save(dir + "/cloud_file/ascii_ply", fileWithPrefix(1, dir + "/tmp.ply"));
  ply.write(dir + "/tmp.ply", cloud, true);
  save(dir + "/cloud_file/binary_ply", fileWithPrefix(1, dir + "/tmp.ply"));
  std::remove((dir + "/tmp.pcd").c_str());
  std::remove((dir + "/tmp.ply").c_str());

  // Depth image: rows-1, cols-1, metres flag, fx fy cx cy, scale, quaternion, pixels: a level
  // camera 1.5 m above a floor, looking down.
  for (std::uint8_t metres : {0, 1}) {
    std::vector<std::uint8_t> seed;
    put(seed, std::uint8_t(31));
    put(seed, std::uint8_t(31));
    put(seed, metres);
    for (float v : {40.0f, 40.0f, 16.0f, 16.0f, 1000.0f, 1.0f, 0.0f, 0.0f, 0.0f}) put(seed, v);
    for (int p = 0; p < 32 * 32; ++p) {
      if (metres) {
        put(seed, 1.5f);
      } else {
        put(seed, std::uint16_t(1500));
      }
    }
    save(dir + "/depth_image/seed_" + std::to_string(metres), seed);
  }
  std::cout << "make_seeds: wrote seeds into " << dir << "\n";
  return 0;
}
