#pragma once
// An assembled Jacobian against its finite differences, column by column: the worst distance of
// a column relative to the differences' column size (their noise ~1e-7 of it), and how many
// columns the differences see as zero while the assembled one is not.
#include <algorithm>

#include <Eigen/Dense>

namespace rollgap::test {

struct ColumnDistance {
    double worst = 0.0;          // max_k |J_k - D_k| / |D_k| over the non-zero columns of D
    int nonzero_where_zero = 0;  // columns with D_k = 0 but J_k != 0
};

inline ColumnDistance column_distance(const Eigen::MatrixXd& assembled,
                                      const Eigen::MatrixXd& differences) {
    ColumnDistance out;
    for (Eigen::Index k = 0; k < differences.cols(); ++k) {
        const double scale = differences.col(k).norm();
        if (scale == 0.0) {
            if (assembled.col(k).norm() != 0.0) ++out.nonzero_where_zero;
            continue;
        }
        out.worst = std::max(out.worst, (assembled.col(k) - differences.col(k)).norm() / scale);
    }
    return out;
}

}  // namespace rollgap::test
