!> Exact consistent-mass solves on tensor-product lattices: MASS SOLVER=KRONECKER
!! (doc/theory.md §5.2).
!!
!! * **Kronecker blocks.** On a NURBS patch whose geometry and weights are separable (a
!!   rectangle refined in any way, graded knots included), and on a grid of Q4 or Q9 elements
!!   with axis-parallel sides, the consistent mass of each displacement component is a
!!   Kronecker product M = A1 (x) A2 of two banded 1D masses (half bandwidth p). Its inverse
!!   A1^-1 (x) A2^-1 is two sweeps of banded Cholesky solves, one along each lattice
!!   direction: O(n) work, no stored factor beyond the 1D ones (the structure Gao & Calo,
!!   CMAME 2014, use for explicit IGA). A1 and A2 are read off the assembled M.
!! * **Serendipity blocks.** On a grid of Q8 elements with axis-parallel sides the mass is not
!!   a Kronecker product, but the serendipity space is the biquadratic one without the
!!   bubble (x) bubble functions of the hierarchical basis (vertex hats V and element bubbles B
!!   in each direction): Q8 = span{V(x)V, V(x)B, B(x)V}. So its mass is the principal
!!   submatrix of the Q9 mass Â1 (x) Â2 (hierarchical 1D masses from the node coordinates)
!!   without the B x B rows. With S the Kronecker inverse and E the B x B selection, the
!!   capacitance formula gives the solve x = S g - S E (E^T S E)^-1 E^T S g, and
!!   E^T S E = (Â1^-1)_BB (x) (Â2^-1)_BB is again a Kronecker product whose factors have the
!!   Schur complements Â_BB - Â_BV Â_VV^-1 Â_VB as inverses (tridiagonal solves). One solve:
!!   two Kronecker solves, one Schur product on the element lattice, two basis changes.
!! * **Dirichlet conditions.** A lattice line fixed in a component becomes an identity row of
!!   that component's 1D matrix (for Q8 only vertex lines). Other fixed dofs (say the one
!!   point of a roller edge fixed along the edge) are up to `max_points` isolated points: a
!!   second capacitance correction with the responses to unit loads there, computed once.
!!
!! `tensor_layout` (tensor_layout.f90) finds the lattices in the model; `tensor_mass_setup`
!! (tensor_setup.f90) builds the 1D matrices and proves the result: M v for pseudo-random v
!! must solve back to v within 1e-9 (relative), so a mesh that only looks like a lattice (a
!! distorted grid, a non-uniform density, weights that are not separable) is refused with the
!! reason, and the caller falls back to another solver. `tensor_mass_solve` and
!! `tensor_mass_step` (tensor_solve.f90) run the sweeps of tensor_kernels.inc (direct blocks,
!! loads and stores of lattice columns) and tensor_q8.inc (serendipity blocks); the solve
!! allocates nothing. This module holds the types and constants they share.
module ictus_solver_tensor_types
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: lattice_t, tensor_layout_t, band_t, cond_t, comp_t, tblock_t, tensor_mass_t, &
      TENSOR_DIRECT, TENSOR_SERENDIPITY, max_points, check_tol, col_block

  !> Block kinds: a Kronecker-product mass, or the Q8 mass inside the Q9 one.
  integer, parameter :: TENSOR_DIRECT = 1, TENSOR_SERENDIPITY = 2
  !> Most isolated fixed points per block and component (each costs one lattice-sized
  !! response vector and one pass per solve).
  integer, parameter :: max_points = 8
  !> Relative error of the set-up check M v -> v above which the lattice is refused.
  real(dp), parameter :: check_tol = 1.0e-9_dp
  !> Columns solved together along direction 1: their recurrences run as one vector of
  !! col_block lanes (4 AVX-512 registers), whose last kd values stay in registers.
  integer, parameter :: col_block = 32

  !> One lattice as found in the model: n(1) x n(2) points, the node at each (0: none, the
  !! centre of a Q8 element), and for Q8 the coordinate of each lattice line.
  type :: lattice_t
    integer :: kind = TENSOR_DIRECT
    integer :: n(2) = 0
    integer, allocatable :: node(:,:)
    real(dp), allocatable :: x1(:), x2(:)
    !> What the lattice is, for the log (e.g. "patch BODY", "Q8 grid").
    character(len=:), allocatable :: what
  end type lattice_t

  !> The lattices of a model (nblocks = 0 when it has none; `reason` says why).
  type :: tensor_layout_t
    integer :: nblocks = 0
    type(lattice_t), allocatable :: b(:)
    character(len=:), allocatable :: reason
  end type tensor_layout_t

  !> A symmetric band matrix a(k, i) = A(i, i - k), k = 0..kd, and its Cholesky factor
  !! l(0, i) = 1/L(i, i), l(k, i) = L(i, i - k).
  type :: band_t
    integer :: n = 0
    integer :: kd = 0
    real(dp), allocatable :: a(:,:), l(:,:)
  end type band_t

  !> A hierarchical 1D Q8 mass A (vertex v at 2v - 1, the bubble of element e at 2e) in
  !! condensed form: A_BB is diagonal (the bubbles of two elements do not overlap), so
  !! A^-1 y = expand(S^-1 condense(y)) with the tridiagonal vertex Schur complement
  !! S = A_VV - A_VB A_BB^-1 A_BV (its Cholesky factor in sv), condense(y)_v =
  !! y_v - pr(v-1) y_(bubble v-1) - pl(v) y_(bubble v), and the bubbles expanded as
  !! x_e = ab(e) y_e - pl(e) x_(vertex e) - pr(e) x_(vertex e+1), where ab = 1/A_BB and
  !! pl, pr are the bubble's couplings to its left and right vertex times ab. Half the lines
  !! and half the band of the banded factor of A.
  type :: cond_t
    type(band_t) :: sv
    real(dp), allocatable :: ab(:), pl(:), pr(:)
    !> The entries themselves, per bubble e (contiguous, for the Schur products): A_BB(e),
    !! and its couplings cl(e), cr(e) to its left and right vertex.
    real(dp), allocatable :: abb(:), cl(:), cr(:)
  end type cond_t

  !> One component of one block: the fixed lines of each direction (fix1, fix2; rows1 lists
  !! those of direction 1), the 1D matrices with the fixed lines as identity rows
  !! (hierarchical for Q8), the factor of their vertex parts and their condensed forms (Q8),
  !! and the isolated fixed points with their unit responses w(:, :, k), the lattice
  !! box(1:4, k) = i1, i2, j1, j2
  !! outside which |w(:, :, k)| < 1e-18 max |w(:, :, k)| (the inverse of a mass matrix decays
  !! exponentially away from the load), and the Cholesky factor h of the capacitance matrix
  !! H(l, k) = w(pts(l), k).
  type :: comp_t
    type(band_t) :: m(2)
    type(band_t) :: v(2)
    type(cond_t) :: q(2)
    logical, allocatable :: fix1(:), fix2(:)
    integer, allocatable :: rows1(:)
    integer :: npts = 0
    integer, allocatable :: pts(:,:), box(:,:)
    real(dp), allocatable :: w(:,:,:), h(:,:), beta(:)
  end type comp_t

  !> One block: its kind and lattice (with kfirst(j) the first node of column j when the
  !! nodes of that column are numbered one after the other, 0 otherwise), both components,
  !! and the work arrays of a solve: the lattice z(:, :, c) of each component, the B x B
  !! values r and the Schur work t (direction 2) and tv (direction 1) of Q8, and a ring of
  !! columns (Q8: the last loads of a forward block, the last back-substituted vertex
  !! columns), a block zb of bubble columns (their indices jb) and the work lt of
  !! `lines_solve`.
  type :: tblock_t
    integer :: kind = TENSOR_DIRECT
    integer :: n(2) = 0
    integer :: ne(2) = 0
    integer, allocatable :: node(:,:), kfirst(:)
    !> The columns in the boxes of the point corrections (stored once those are known).
    logical, allocatable :: defer(:)
    type(comp_t) :: c(2)
    real(dp), allocatable :: z(:,:,:), r(:,:,:), t(:,:), tv(:,:), ring(:,:), zb(:,:), lt(:,:)
    integer, allocatable :: jb(:)
    !> One column of nodal values on its way out of `store` (2, n(1)).
    real(dp), allocatable :: xc(:,:)
    character(len=:), allocatable :: what
  end type tblock_t

  !> The solver: its blocks and the nodes outside every block (massless: zero result).
  type :: tensor_mass_t
    integer :: nblocks = 0
    type(tblock_t), allocatable :: b(:)
    integer, allocatable :: outside(:)
  end type tensor_mass_t
end module ictus_solver_tensor_types
