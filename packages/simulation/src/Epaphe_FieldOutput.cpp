#include "Epaphe_FieldOutput.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_ReducedThermal.hpp"

#include <fstream>
#include <iomanip>
#include <sstream>

namespace epaphe {

struct FieldOutput::BodyFields {
  NodeRecovery R;  // u = R q of every node
  DenseVector uAll;
  std::vector<double> frame;
  std::unique_ptr<io::Series> position, displacement;
  const ThermalIntegrator* thermal = nullptr;  // with a thermal model: its temperature field
  std::unique_ptr<io::Series> temperature;
  std::vector<double> T;
};

FieldOutput::FieldOutput(io::Hdf5File& file, const std::vector<std::unique_ptr<SceneBody>>& bodies,
                         const std::vector<const BSplineSurface*>& drawn, int every, bool fresh)
    : file_(file), bodies_(bodies), drawn_(drawn), every_(every), time_(file, "/fields/time", {}) {
  for (const auto& bp : bodies_) {
    const SceneBody& b = *bp;
    auto r = std::make_unique<BodyFields>();
    const std::string g = "/bodies/" + b.name;
    const std::uint64_t nn = static_cast<std::uint64_t>(b.rom->numNodes());
    std::vector<long long> hex;
    for (const auto& e : b.rom->hexes) hex.insert(hex.end(), e.begin(), e.end());
    if (fresh) {
      file.writeInts(g + "/mesh/hexahedra", {static_cast<std::uint64_t>(b.rom->hexes.size()), 8}, hex.data());
      file.writeDoubles(g + "/mesh/coordinates", {nn, 3}, b.rom->coords.empty() ? nullptr : b.rom->coords[0].data());
    }
    std::vector<int> all(nn);
    for (std::uint64_t k = 0; k < nn; ++k) all[k] = static_cast<int>(k);
    r->R = NodeRecovery(*b.rom, all, "epaphe::fields::R");
    r->uAll = DenseVector("epaphe::fields::u", 3 * nn);
    r->frame.resize(3 * nn);
    r->position = std::make_unique<io::Series>(file, g + "/fields/position", std::vector<std::uint64_t>{nn, 3}, 16);
    r->displacement =
        std::make_unique<io::Series>(file, g + "/fields/displacement", std::vector<std::uint64_t>{nn, 3}, 16);
    perBody_.push_back(std::move(r));
  }
  for (const BSplineSurface* surf : drawn_) {
    if (!fresh) break;
    std::vector<double> pts;
    for (int i = 0; i < surf->nu(); ++i)
      for (int j = 0; j < surf->nv(); ++j) {
        const auto p = surf->gridPoint(i, j);
        pts.insert(pts.end(), p.begin(), p.end());
      }
    file.writeDoubles("/surfaces/" + surf->name() + "/points",
                      {static_cast<std::uint64_t>(surf->nu()) * static_cast<std::uint64_t>(surf->nv()), 3}, pts.data());
  }
}

FieldOutput::~FieldOutput() = default;

void FieldOutput::setTemperature(int body, const ThermalIntegrator* integrator) {
  BodyFields& r = *perBody_.at(static_cast<std::size_t>(body));
  const SceneBody& b = *bodies_[static_cast<std::size_t>(body)];
  const std::uint64_t nn = static_cast<std::uint64_t>(b.rom->numNodes());
  EPAPHE_REQUIRE(integrator != nullptr && static_cast<std::uint64_t>(integrator->numNodes()) == nn,
                 "body '" << b.name << "': its thermal model's mesh is not its mechanical model's (" << nn
                          << " nodes); no temperature field can be drawn on it");
  r.thermal = integrator;
  r.T.resize(nn);
  r.temperature = std::make_unique<io::Series>(file_, "/bodies/" + b.name + "/fields/temperature",
                                               std::vector<std::uint64_t>{nn}, 16);
}

std::vector<io::Series*> FieldOutput::series() {
  std::vector<io::Series*> s;
  for (const auto& r : perBody_) {
    s.push_back(r->position.get());
    s.push_back(r->displacement.get());
    if (r->temperature) s.push_back(r->temperature.get());
  }
  s.push_back(&time_);
  return s;
}

void FieldOutput::afterCorrect(ExplicitLoop& loop) {
  if (loop.step() % every_ != 0 && !loop.lastStep()) return;
  ScopedPhase phase(loop.cost(), "output");
  const double t = loop.time();
  time_.append(&t);
  for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
    BodyFields& r = *perBody_[ib];
    r.R.apply(loop.part(loop.current(), ib), r.uAll);  // u = R q (eq. 2.5)
    auto uh = Kokkos::create_mirror_view(r.uAll);
    Kokkos::deep_copy(uh, r.uAll);
    const auto& X = bodies_[ib]->rom->coords;
    r.displacement->append(uh.data());
    for (std::size_t k = 0; k < r.frame.size(); ++k) r.frame[k] = X[k / 3][k % 3] + uh(k);
    r.position->append(r.frame.data());
    if (r.thermal) {
      for (std::size_t n = 0; n < r.T.size(); ++n) r.T[n] = r.thermal->temperature(static_cast<int>(n));
      r.temperature->append(r.T.data());
    }
  }
}

void FieldOutput::writeXdmf(const std::string& h5path, const std::string& xmfPath) const {
  std::string h5 = h5path;
  if (const auto slash = h5.rfind('/'); slash != std::string::npos) h5 = h5.substr(slash + 1);
  io::Hdf5File file(h5path, io::Hdf5File::Mode::ReadOnly);
  const auto times = file.readDoubles("/fields/time");
  const long long frames = static_cast<long long>(times.size());
  std::ostringstream x;
  x << std::setprecision(17);
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"2.0\">\n <Domain>\n";
  for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
    const auto& b = bodies_[ib];
    const bool hot = perBody_[ib]->thermal != nullptr;
    const std::string g = "/bodies/" + b->name;
    const long long nn = b->rom->numNodes(), ne = static_cast<long long>(b->rom->hexes.size());
    auto slab = [&](long long k, const std::string& dataset) {
      std::ostringstream s;
      s << "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" << nn << " 3\" Type=\"HyperSlab\">"
        << "<DataItem Dimensions=\"3 3\" Format=\"XML\">" << k << " 0 0 1 1 1 1 " << nn << " 3</DataItem>"
        << "<DataItem Dimensions=\"" << frames << " " << nn << " 3\" NumberType=\"Float\" Precision=\"8\" "
        << "Format=\"HDF\">" << h5 << ":" << g << "/fields/" << dataset << "</DataItem></DataItem>";
      return s.str();
    };
    x << "  <Grid Name=\"" << b->name << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (long long k = 0; k < frames; ++k) {
      x << "   <Grid Name=\"" << b->name << "\" GridType=\"Uniform\"><Time Value=\"" << times[k] << "\"/>\n"
        << "    <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << ne << "\"><DataItem Dimensions=\"" << ne
        << " 8\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" << h5 << ":" << g
        << "/mesh/hexahedra</DataItem></Topology>\n"
        << "    <Geometry GeometryType=\"XYZ\">" << slab(k, "position") << "</Geometry>\n"
        << "    <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">" << slab(k, "displacement")
        << "</Attribute>\n";
      if (hot)
        x << "    <Attribute Name=\"temperature\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
          << "ItemType=\"HyperSlab\" Dimensions=\"" << nn << "\" Type=\"HyperSlab\"><DataItem Dimensions=\"3 2\" "
          << "Format=\"XML\">" << k << " 0 1 1 1 " << nn << "</DataItem><DataItem Dimensions=\"" << frames << " " << nn
          << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":" << g
          << "/fields/temperature</DataItem></DataItem></Attribute>\n";
      x << "   </Grid>\n";
    }
    x << "  </Grid>\n";
  }
  for (const BSplineSurface* s : drawn_) {
    const int nu = s->nu(), nv = s->nv();
    std::ostringstream quads;
    for (int i = 0; i + 1 < nu; ++i)
      for (int j = 0; j + 1 < nv; ++j)
        quads << i * nv + j << " " << (i + 1) * nv + j << " " << (i + 1) * nv + j + 1 << " " << i * nv + j + 1 << " ";
    x << "  <Grid Name=\"" << s->name() << "\" GridType=\"Uniform\">\n"
      << "   <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << (nu - 1) * (nv - 1)
      << "\"><DataItem Dimensions=\"" << (nu - 1) * (nv - 1) << " 4\" NumberType=\"Int\" Format=\"XML\">" << quads.str()
      << "</DataItem></Topology>\n"
      << "   <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"" << nu * nv << " 3\" NumberType=\"Float\" "
      << "Precision=\"8\" Format=\"HDF\">" << h5 << ":/surfaces/" << s->name() << "/points</DataItem></Geometry>\n"
      << "  </Grid>\n";
  }
  for (const std::string& name : coatings_) {  // the coating's elements, their wear per wear record
    const std::string g = "/coating/" + name;
    const auto wt = file.readDoubles(g + "/time");
    const auto el = file.readInts(g + "/elements");
    const long long ne = el.at(0) * el.at(1), nw = static_cast<long long>(wt.size());
    x << "  <Grid Name=\"" << name << " coating\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (long long k = 0; k < nw; ++k)
      x << "   <Grid Name=\"" << name << " coating\" GridType=\"Uniform\"><Time Value=\"" << wt[k] << "\"/>\n"
        << "    <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << ne << "\"><DataItem Dimensions=\""
        << ne << " 4\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" << h5 << ":" << g
        << "/mesh/quads</DataItem></Topology>\n"
        << "    <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"" << 4 * ne << " 3\" NumberType=\"Float\" "
        << "Precision=\"8\" Format=\"HDF\">" << h5 << ":" << g << "/mesh/points</DataItem></Geometry>\n"
        << "    <Attribute Name=\"wear\" AttributeType=\"Scalar\" Center=\"Cell\"><DataItem ItemType=\"HyperSlab\" "
        << "Dimensions=\"" << ne << "\" Type=\"HyperSlab\"><DataItem Dimensions=\"3 3\" Format=\"XML\">" << k
        << " 0 0 1 1 1 1 " << el[0] << " " << el[1] << "</DataItem><DataItem Dimensions=\"" << nw << " " << el[0] << " "
        << el[1] << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":" << g
        << "/wear</DataItem></DataItem></Attribute>\n   </Grid>\n";
    x << "  </Grid>\n";
  }
  x << " </Domain>\n</Xdmf>\n";
  std::ofstream out(xmfPath);
  EPAPHE_REQUIRE(out, "cannot write the XDMF file " << xmfPath << ": check the directory's permissions");
  out << x.str();
}

}  // namespace epaphe
