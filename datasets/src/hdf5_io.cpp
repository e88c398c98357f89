// HDF5 translation unit: reading and writing the datasets of YCB raw captures.
#include "hdf5_io.h"

#include <H5Cpp.h>

#include <filesystem>

#include "skelgrasp/common/error.h"

namespace skelgrasp::datasets::detail {
namespace {

void quietHdf5() {
  static const bool once = [] {
    H5::Exception::dontPrint();  // errors become IoError lines, not HDF5 stack dumps
    return true;
  }();
  (void)once;
}

std::string describe(const H5::Exception& e) {
  const std::string detail = e.getDetailMsg();
  return detail.empty() ? "HDF5 error" : detail;
}

}  // namespace

struct Hdf5Reader::Impl {
  std::string path;
  H5::H5File file;
};

Hdf5Reader::Hdf5Reader(const std::string& path) : impl_(new Impl) {
  quietHdf5();
  impl_->path = path;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError(path, "no such file");
  try {
    if (!H5::H5File::isHdf5(path)) throw IoError(path, "not an HDF5 file");
    impl_->file.openFile(path, H5F_ACC_RDONLY);
  } catch (const H5::Exception& e) {
    throw IoError(path, "cannot open HDF5 file: " + describe(e));
  }
}

Hdf5Reader::~Hdf5Reader() = default;

bool Hdf5Reader::has(const std::string& dataset) const {
  try {
    return impl_->file.nameExists(dataset);
  } catch (const H5::Exception&) {
    return false;
  }
}

Eigen::MatrixXd Hdf5Reader::matrix(const std::string& dataset) const {
  if (!has(dataset)) throw IoError(impl_->path, "no dataset '" + dataset + "'");
  try {
    const H5::DataSet set = impl_->file.openDataSet(dataset);
    if (set.getTypeClass() != H5T_INTEGER && set.getTypeClass() != H5T_FLOAT) {
      throw IoError(impl_->path, "dataset '" + dataset + "' is not numeric");
    }
    const H5::DataSpace space = set.getSpace();
    const int rank = space.getSimpleExtentNdims();
    if (rank > 2) {
      throw IoError(impl_->path, "dataset '" + dataset + "' has rank " + std::to_string(rank));
    }
    hsize_t dims[2] = {1, 1};
    if (rank > 0) space.getSimpleExtentDims(dims);
    const auto rows = static_cast<Eigen::Index>(dims[0]);
    const auto cols = static_cast<Eigen::Index>(rank == 2 ? dims[1] : 1);
    // HDF5 stores row-major; read into a row-major buffer and let Eigen copy.
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> buffer(rows, cols);
    set.read(buffer.data(), H5::PredType::NATIVE_DOUBLE);
    return buffer;
  } catch (const H5::Exception& e) {
    throw IoError(impl_->path, "cannot read dataset '" + dataset + "': " + describe(e));
  }
}

double Hdf5Reader::scalar(const std::string& dataset) const {
  const Eigen::MatrixXd m = matrix(dataset);
  if (m.size() != 1) {
    throw IoError(impl_->path, "dataset '" + dataset + "' should hold one number, holds " +
                                   std::to_string(m.size()));
  }
  return m(0, 0);
}

perception::Image<std::uint16_t> Hdf5Reader::uint16Image(const std::string& dataset) const {
  if (!has(dataset)) throw IoError(impl_->path, "no dataset '" + dataset + "'");
  try {
    const H5::DataSet set = impl_->file.openDataSet(dataset);
    if (set.getTypeClass() != H5T_INTEGER && set.getTypeClass() != H5T_FLOAT) {
      throw IoError(impl_->path, "dataset '" + dataset + "' is not numeric");
    }
    const H5::DataSpace space = set.getSpace();
    if (space.getSimpleExtentNdims() != 2) {
      throw IoError(impl_->path, "dataset '" + dataset + "' is not a 2-D image");
    }
    hsize_t dims[2];
    space.getSimpleExtentDims(dims);
    perception::Image<std::uint16_t> image(static_cast<int>(dims[1]), static_cast<int>(dims[0]));
    set.read(image.data.data(), H5::PredType::NATIVE_UINT16);
    return image;
  } catch (const H5::Exception& e) {
    throw IoError(impl_->path, "cannot read dataset '" + dataset + "': " + describe(e));
  }
}

struct Hdf5Writer::Impl {
  std::string path;
  H5::H5File file;
};

Hdf5Writer::Hdf5Writer(const std::string& path) : impl_(new Impl) {
  quietHdf5();
  impl_->path = path;
  const auto parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  try {
    impl_->file = H5::H5File(path, H5F_ACC_TRUNC);
  } catch (const H5::Exception& e) {
    throw IoError(path, "cannot create HDF5 file: " + describe(e));
  }
}

Hdf5Writer::~Hdf5Writer() = default;

void Hdf5Writer::matrix(const std::string& dataset, const Eigen::MatrixXd& value) {
  try {
    const hsize_t dims[2] = {static_cast<hsize_t>(value.rows()),
                             static_cast<hsize_t>(value.cols())};
    const H5::DataSpace space(2, dims);
    H5::DataSet set = impl_->file.createDataSet(dataset, H5::PredType::NATIVE_DOUBLE, space);
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> buffer = value;
    set.write(buffer.data(), H5::PredType::NATIVE_DOUBLE);
  } catch (const H5::Exception& e) {
    throw IoError(impl_->path, "cannot write dataset '" + dataset + "': " + describe(e));
  }
}

void Hdf5Writer::scalar(const std::string& dataset, double value) {
  try {
    H5::DataSet set =
        impl_->file.createDataSet(dataset, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR));
    set.write(&value, H5::PredType::NATIVE_DOUBLE);
  } catch (const H5::Exception& e) {
    throw IoError(impl_->path, "cannot write dataset '" + dataset + "': " + describe(e));
  }
}

void Hdf5Writer::uint16Image(const std::string& dataset,
                             const perception::Image<std::uint16_t>& image) {
  try {
    const hsize_t dims[2] = {static_cast<hsize_t>(image.height), static_cast<hsize_t>(image.width)};
    const H5::DataSpace space(2, dims);
    H5::DataSet set = impl_->file.createDataSet(dataset, H5::PredType::NATIVE_UINT16, space);
    set.write(image.data.data(), H5::PredType::NATIVE_UINT16);
  } catch (const H5::Exception& e) {
    throw IoError(impl_->path, "cannot write dataset '" + dataset + "': " + describe(e));
  }
}

}  // namespace skelgrasp::datasets::detail
