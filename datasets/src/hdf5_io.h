#pragma once
// Private to datasets/: the one place where skelgrasp meets the HDF5 C++ API. Every failure is an
// IoError naming the file (and the dataset).
#include <Eigen/Core>

#include <memory>
#include <string>

#include "skelgrasp/perception/image.h"

namespace skelgrasp::datasets::detail {

class Hdf5Reader {
 public:
  explicit Hdf5Reader(const std::string& path);
  ~Hdf5Reader();
  bool has(const std::string& dataset) const;
  // Any numeric dataset of rank 0, 1 or 2 as doubles (rank 0 and 1 become a column).
  Eigen::MatrixXd matrix(const std::string& dataset) const;
  double scalar(const std::string& dataset) const;  // a dataset holding exactly one number
  perception::Image<std::uint16_t> uint16Image(const std::string& dataset) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class Hdf5Writer {
 public:
  explicit Hdf5Writer(const std::string& path);  // creates or truncates
  ~Hdf5Writer();
  void matrix(const std::string& dataset, const Eigen::MatrixXd& value);  // float64, rows x cols
  void scalar(const std::string& dataset, double value);                  // float64, rank 0
  void uint16Image(const std::string& dataset, const perception::Image<std::uint16_t>& image);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace skelgrasp::datasets::detail
