#pragma once
// NumPy <-> Eigen for the module: outputs are new C-order arrays (float64 (n, 3) points, int32
// indices); inputs are read in place when already float64 (or int32) in C order, converted once
// otherwise, and checked for shape and finiteness with a ValueError naming `what`.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "invfem/core/math/types.hpp"

namespace invfem {

namespace py = pybind11;

// Any row-major Eigen matrix of T as a new (rows, cols) array.
template <typename T, typename Matrix>
py::array_t<T> matrix_array(const Matrix& m) {
  py::array_t<T> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  if (m.size() > 0) std::memcpy(a.mutable_data(), m.data(), sizeof(T) * static_cast<std::size_t>(m.size()));
  return a;
}

inline py::array_t<double> points_array(const Points& x) { return matrix_array<double>(x); }
inline py::array_t<double> uv_array(const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>& uv) {
  return matrix_array<double>(uv);
}
template <int Cols>
py::array_t<int> index_array(const Eigen::Matrix<int, Eigen::Dynamic, Cols, Eigen::RowMajor>& m) {
  return matrix_array<int>(m);
}
inline py::array_t<double> vector_array(const Eigen::VectorXd& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  if (v.size() > 0) std::memcpy(a.mutable_data(), v.data(), sizeof(double) * static_cast<std::size_t>(v.size()));
  return a;
}
inline py::array_t<int> int_vector_array(const std::vector<int>& v) {
  py::array_t<int> a(static_cast<py::ssize_t>(v.size()));
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), sizeof(int) * v.size());
  return a;
}

// (n, 3) float64 -> Points; ValueError "<what>: ..." for another shape or a non-finite value.
inline Points points_from(const py::object& object, const std::string& what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!a) throw py::value_error(what + ": expected an array of float64 (n, 3)");
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(what + ": expected shape (n, 3), found " + std::string(py::str(py::object(a.attr("shape")))));
  const Eigen::Map<const Points> view(a.data(), a.shape(0), 3);
  for (Eigen::Index i = 0; i < view.rows(); ++i)
    if (!view.row(i).allFinite()) throw py::value_error(what + ": row " + std::to_string(i) + " is not finite");
  return view;
}

// (m, 3) integers -> Tris; ValueError for another shape or a negative index.
inline Tris tris_from(const py::object& object, const std::string& what) {
  const auto a = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!a) throw py::value_error(what + ": expected an array of integers (m, 3)");
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(what + ": expected shape (m, 3), found " + std::string(py::str(py::object(a.attr("shape")))));
  const Eigen::Map<const Tris> view(a.data(), a.shape(0), 3);
  if (view.size() > 0 && view.minCoeff() < 0) throw py::value_error(what + ": a negative vertex index");
  return view;
}

}  // namespace invfem
