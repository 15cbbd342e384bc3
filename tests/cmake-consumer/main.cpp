// Reads an STL file given on the command line and prints its hole count.
#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

#include <stltopo.h>

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  std::ifstream f(argv[1], std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  stltopo::Mesh mesh;
  stltopo::Status s = stltopo::readStl(bytes.data(), bytes.size(), mesh);
  if (!s.ok()) {
    std::cerr << s.message << "\n";
    return 1;
  }
  stltopo::Topology topo;
  s = stltopo::buildTopology(mesh, topo);
  if (!s.ok()) {
    std::cerr << s.message << "\n";
    return 1;
  }
  std::cout << "holes " << topo.nHoles << "\n";
  return 0;
}
