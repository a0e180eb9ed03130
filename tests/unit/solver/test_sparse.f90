!> Sparse assembly and products against dense matrices built from the same element matrices.
program test_sparse
  use ictus_core_kinds, only: dp
  use ictus_solver_sparse, only: graph_t, bsr_t, csr_t, graph_from_elements, bsr_init, &
      csr_init, bsr_add_element, csr_add_element, bsr_matvec, csr_matvec, csr_row_sums, &
      csr_diagonal, find_col
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("solver/sparse")
  call test_assembly_and_products(t)
  call t%finish()
contains

  !> Three overlapping "elements" on 6 nodes with pseudo-random element matrices.
  subroutine test_assembly_and_products(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: nn = 6, nel = 3, nen = 4
    integer :: conn(nen, nel), nenv(nel), e, a, b, i, j
    real(dp) :: ke(2*nen, 2*nen, nel), me(nen, nen, nel), kd(2*nn, 2*nn), md(nn, nn)
    real(dp) :: x(2, nn), y(2, nn), yd(2*nn), s(nn), d(nn)
    type(graph_t) :: g
    type(bsr_t) :: k
    type(csr_t) :: m
    conn(:, 1) = [1, 2, 5, 4]
    conn(:, 2) = [2, 3, 6, 5]
    conn(:, 3) = [4, 5, 6, 1]
    nenv = nen
    do e = 1, nel
      do j = 1, 2*nen
        do i = 1, 2*nen
          ke(i, j, e) = sin(real(i + 3*j + 7*e, dp))
        end do
      end do
      do j = 1, nen
        do i = 1, nen
          me(i, j, e) = cos(real(2*i + j + 5*e, dp))
        end do
      end do
    end do
    call graph_from_elements(nn, nn, nel, nen, nenv, conn, [(i, i = 1, nn)], g)
    ! neighbours: node 1: 5, node 2: 6, node 3: 4 (not 1 and 4), node 4: 5, nodes 5 and 6: 6
    call t%equal_int(g%row_ptr(nn + 1) - 1, 32, "graph: 32 node pairs share an element")
    call t%true(find_col(g, 3, 4) == 0, "nodes 3 and 4 share no element")
    call t%true(find_col(g, 1, 6) > 0, "find_col finds (1, 6) (element 3)")
    call bsr_init(k, g)
    call csr_init(m, g)
    kd = 0.0_dp
    md = 0.0_dp
    do e = 1, nel
      call bsr_add_element(k, nen, conn(:, e), ke(:, :, e))
      call csr_add_element(m, nen, conn(:, e), me(:, :, e))
      do a = 1, nen
        do b = 1, nen
          kd(2*conn(a, e) - 1:2*conn(a, e), 2*conn(b, e) - 1:2*conn(b, e)) = &
              kd(2*conn(a, e) - 1:2*conn(a, e), 2*conn(b, e) - 1:2*conn(b, e)) &
              + ke(2*a - 1:2*a, 2*b - 1:2*b, e)
          md(conn(a, e), conn(b, e)) = md(conn(a, e), conn(b, e)) + me(a, b, e)
        end do
      end do
    end do
    do i = 1, nn
      x(:, i) = [real(i, dp), 1.0_dp/real(i, dp)]
    end do
    call bsr_matvec(nn, k%g%row_ptr, k%g%col, k%val, x, y)
    yd = matmul(kd, reshape(x, [2*nn]))
    call t%close_abs(maxval(abs(reshape(y, [2*nn]) - yd)), 0.0_dp, 1e-12_dp, "K x = dense K x")
    call csr_matvec(nn, m%g%row_ptr, m%g%col, m%val, x, y)
    call t%close_abs(maxval(abs(y(1, :) - matmul(md, x(1, :)))), 0.0_dp, 1e-12_dp, &
        "M x (component 1) = dense")
    call t%close_abs(maxval(abs(y(2, :) - matmul(md, x(2, :)))), 0.0_dp, 1e-12_dp, &
        "M x (component 2) = dense")
    call csr_row_sums(m, s)
    call t%close_abs(maxval(abs(s - sum(md, dim=2))), 0.0_dp, 1e-12_dp, "row sums")
    call csr_diagonal(m, d)
    call t%close_abs(maxval(abs(d - [(md(i, i), i = 1, nn)])), 0.0_dp, 1e-14_dp, "diagonal")
  end subroutine test_assembly_and_products
end program test_sparse
