!> omega_max with the contact active (contact_omega_max) on two spring bars pressed together,
!! against a dense eigen-solve of the same operators written down by hand, and the bipenalty
!! property of doc/contact.md §6a: with beta = eps_N/eps_m = omega0^2 the largest frequency
!! stays at the one without contact, while plain penalty raises it.
!!
!! Each bar: two rows (y = 0 and y = H) of n + 1 nodes, axial springs ks between neighbours
!! of a row, y fixed, lumped masses m (m/2 at the ends). Bar 1 on [0, L], bar 2 on
!! [L - g, 2L - g] (overlap g). Contact: TWO HALF PASS between the end edges (linear
!! segments, 2 Gauss points). For matching flat edges the two half-passes give the exact
!! penalty stiffness eps [[G, -G], [-G, G]] on the x dofs of the four end nodes, with the
!! edge Gram matrix G = H/6 [[2, 1], [1, 2]]; the bipenalty masses are eps_m wJ R_a (1 + 1)
!! summed over the Gauss points, i.e. 2 eps_m l with l = H/2 per end node.
program test_contact_omega
  use ictus_core_kinds, only: dp
  use ictus_solver_sparse, only: graph_t, bsr_t, csr_t, graph_from_elements, bsr_init, &
      bsr_add_element
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init, mass_set_added, mass_solve
  use ictus_solver_domain, only: domain_t
  use ictus_test_solver, only: domain_init_serial
  use ictus_solver_contact_step, only: contact_step_t, contact_step_init, &
      contact_bipenalty_init, contact_omega_max
  use ictus_contact_contact, only: contact_t, contact_init, contact_define_pair, &
      contact_setup, PAIR_TWO_HALF_PASS
  use ictus_contact_surface, only: surface_init, SEG_LAGRANGE
  use ictus_test_check, only: checker_t
  implicit none
  interface
    subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
      import :: dp
      character, intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      real(dp), intent(inout) :: a(lda, *)
      real(dp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsyev
  end interface
  integer, parameter :: n = 10, nb = 2*(n + 1), nn = 2*nb
  real(dp), parameter :: ks = 100.0_dp, m = 1.0_dp, hgt = 1.0_dp, gap = 1.0e-3_dp
  type(checker_t) :: t
  call t%start("solver/contact_omega")
  call two_bars(t)
  call added_mass(t)
  call t%finish()
contains

  !> Global node of bar b (1, 2), row r (0, 1), position i (0..n).
  pure integer function node(b, r, i)
    integer, intent(in) :: b, r, i
    node = (b - 1)*nb + r*(n + 1) + i + 1
  end function node

  subroutine two_bars(t)
    type(checker_t), intent(inout) :: t
    type(graph_t) :: g
    type(bsr_t) :: k
    type(csr_t) :: mc
    type(mass_op_t) :: op
    type(domain_t) :: dom
    type(contact_t) :: c
    type(contact_step_t) :: cs
    integer :: conn(2, 4*n), nen(4*n), e, b, r, i, iters, cn(2, 1)
    real(dp) :: x0(2, nn), md(nn), ke(4, 4), u(2, nn)
    real(dp) :: omega0, om_plain, om_bip, ref0, ref_plain, ref_bip, eps, eps_m, ell
    logical :: fixed(2, nn)
    ! mesh
    e = 0
    do b = 1, 2
      do r = 0, 1
        do i = 0, n
          x0(:, node(b, r, i)) = [real(i, dp) + real(b - 1, dp)*(real(n, dp) - gap), &
              real(r, dp)*hgt]
          md(node(b, r, i)) = merge(0.5_dp*m, m, i == 0 .or. i == n)
          if (i < n) then
            e = e + 1
            conn(:, e) = [node(b, r, i), node(b, r, i + 1)]
          end if
        end do
      end do
    end do
    nen = 2
    call graph_from_elements(nn, nn, 4*n, 2, nen, conn, [(i, i = 1, nn)], g)
    call bsr_init(k, g)
    ke = 0.0_dp
    ke(1, 1) = ks
    ke(3, 3) = ks
    ke(1, 3) = -ks
    ke(3, 1) = -ks
    do e = 1, 4*n
      call bsr_add_element(k, 2, conn(:, e), ke)
    end do
    fixed = .false.
    fixed(2, :) = .true.
    call domain_init_serial(dom, nn)
    call mass_op_init(op, dom, .false., mc, md, fixed)
    ! free-free chains with end masses m/2: the zigzag mode u_i = (-1)^i has omega^2 = 4 ks/m
    omega0 = 2.0_dp*sqrt(ks/m)
    ell = 0.5_dp*hgt
    ref0 = dense_omega(conn, md, ell, 0.0_dp, 0.0_dp)
    call t%close(ref0, omega0, 1.0e-12_dp, 'dense reference without contact = 2 sqrt(ks/m)')
    ! contact: bar 1's right edge (upwards), bar 2's left edge (downwards): counter-clockwise
    eps = 1.0e3_dp*ks/ell    ! penalty spring per node 1000 times the bar spring
    call contact_init(c, 2, 1)
    cn(:, 1) = [node(1, 0, n), node(1, 1, n)]
    call surface_init(c%surfaces(1), 'right1', [SEG_LAGRANGE], [2], cn, x0)
    cn(:, 1) = [node(2, 1, 0), node(2, 0, 0)]
    call surface_init(c%surfaces(2), 'left2', [SEG_LAGRANGE], [2], cn, x0)
    call contact_define_pair(c, 1, 'bars', PAIR_TWO_HALF_PASS, eps, 1, 2)
    call contact_setup(c)
    call contact_step_init(cs, c, x0, dom)
    ! bars pulled apart (gap open): the contact adds nothing
    u = 0.0_dp
    u(1, nb + 1:nn) = 2.0_dp*gap
    call contact_omega_max(cs, c, k, op, dom, x0, u, om_plain, iters, 1.0e-12_dp, 50000)
    call t%close(om_plain, omega0, 1.0e-6_dp, 'contact_omega_max with the contact open')
    u = 0.0_dp
    call contact_omega_max(cs, c, k, op, dom, x0, u, om_plain, iters, 1.0e-12_dp, 50000)
    call t%equal_int(c%pairs(1)%active_points, 4, 'all four Gauss points in contact')
    ref_plain = dense_omega(conn, md, ell, eps, 0.0_dp)
    call t%close(om_plain, ref_plain, 1.0e-5_dp, 'plain penalty: omega_max against the '// &
        'dense eigen-solve of K + eps [[G, -G], [-G, G]]')
    ! doc/contact.md §6: lambda ~ eps l (1/m_s + 1/m_m) for a stiff penalty
    call t%close(om_plain, sqrt(eps*ell*(2.0_dp/(0.5_dp*m))), 0.02_dp, &
        'plain penalty: omega_max ~ sqrt(eps l (1/m_s + 1/m_m)) (doc/contact.md §6)')
    call t%true(om_plain > 5.0_dp*omega0, 'plain penalty raises omega_max (x5 or more)')
    ! bipenalty with beta = omega0^2 (the dt given is small, so 1/(2 dt^2) > omega0^2)
    c%pairs(1)%mass_penalty = 0.0_dp
    call contact_bipenalty_init(cs, c, op, omega0, 1.0e-6_dp)
    eps_m = c%pairs(1)%eps_m
    call t%close(eps_m, eps/omega0**2, 1.0e-14_dp, 'AUTO: eps_m = eps_N/omega0^2')
    call contact_omega_max(cs, c, k, op, dom, x0, u, om_bip, iters, 1.0e-12_dp, 50000)
    ref_bip = dense_omega(conn, md, ell, eps, eps_m)
    print '(a, 4es22.14)', '  omega0, plain, bipenalty, dense bipenalty: ', omega0, &
        om_plain, om_bip, ref_bip
    call t%close(om_bip, ref_bip, 1.0e-5_dp, 'bipenalty: omega_max against the dense '// &
        'eigen-solve with masses m + 2 eps_m l at the end nodes')
    call t%close(om_bip, omega0, 0.01_dp, 'bipenalty: omega_max stays at the value '// &
        'without contact (1 %)')
    call t%true(om_bip <= omega0*(1.0_dp + 1.0e-6_dp), 'bipenalty: mediant bound '// &
        'omega_max <= max(omega0, sqrt(beta))')
    ! AUTO with the bulk step dt = 0.9*2/omega0: beta = 1/(2 dt^2) < omega0^2
    call contact_bipenalty_init(cs, c, op, omega0, 1.8_dp/omega0)
    call t%close(c%pairs(1)%eps_m, eps*2.0_dp*(1.8_dp/omega0)**2, 1.0e-14_dp, &
        'AUTO at dt = 0.9 dt_crit: eps_m = 2 eps_N dt^2')
    c%pairs(1)%mass_penalty = 3.5_dp
    call contact_bipenalty_init(cs, c, op, omega0, 1.8_dp/omega0)
    call t%close(c%pairs(1)%eps_m, 3.5_dp, 0.0_dp, 'MASS PENALTY=value: eps_m = value')
  end subroutine two_bars

  !> Dense reference: sqrt of the largest eigenvalue of (M + D)^-1/2 (K + K_p) (M + D)^-1/2
  !! on the x dofs, K_p = eps [[G, -G], [-G, G]] on the end nodes, D = 2 eps_m l there.
  real(dp) function dense_omega(conn, md, ell, epsp, epsm) result(om)
    integer, intent(in) :: conn(:,:)
    real(dp), intent(in) :: md(:), ell, epsp, epsm
    real(dp) :: a(nn, nn), w(nn), work(8*nn), mm(nn), sgn(4)
    real(dp) :: gram(2, 2)
    integer :: ends(4), p, q, info, e
    a = 0.0_dp
    do e = 1, 4*n
      a(conn(1, e), conn(1, e)) = a(conn(1, e), conn(1, e)) + ks
      a(conn(2, e), conn(2, e)) = a(conn(2, e), conn(2, e)) + ks
      a(conn(1, e), conn(2, e)) = a(conn(1, e), conn(2, e)) - ks
      a(conn(2, e), conn(1, e)) = a(conn(2, e), conn(1, e)) - ks
    end do
    gram = hgt/6.0_dp*reshape([2.0_dp, 1.0_dp, 1.0_dp, 2.0_dp], [2, 2])
    ! end nodes in edge order: bar 1 (rows 0, 1), bar 2 (rows 0, 1); same y pairs up
    ends = [node(1, 0, n), node(1, 1, n), node(2, 0, 0), node(2, 1, 0)]
    sgn = [1.0_dp, 1.0_dp, -1.0_dp, -1.0_dp]
    do p = 1, 4
      do q = 1, 4
        a(ends(p), ends(q)) = a(ends(p), ends(q)) + epsp*sgn(p)*sgn(q)* &
            gram(mod(p - 1, 2) + 1, mod(q - 1, 2) + 1)
      end do
    end do
    mm = md
    mm(ends) = mm(ends) + 2.0_dp*epsm*ell
    do q = 1, nn
      a(:, q) = a(:, q)/sqrt(mm*mm(q))
    end do
    call dsyev('N', 'U', nn, a, nn, w, work, size(work), info)
    om = sqrt(w(nn))
  end function dense_omega

  !> mass_set_added: a = f/(m + dm) on free dofs, 0 on fixed ones, restored by dm = 0.
  subroutine added_mass(t)
    type(checker_t), intent(inout) :: t
    type(mass_op_t) :: op
    type(domain_t) :: dom
    type(csr_t) :: mc
    logical :: fixed(2, 3)
    real(dp) :: f(2, 3), a(2, 3)
    integer :: ierr
    fixed = .false.
    fixed(2, 2) = .true.
    call domain_init_serial(dom, 3)
    call mass_op_init(op, dom, .false., mc, [1.0_dp, 2.0_dp, 4.0_dp], fixed)
    f = 1.0_dp
    call mass_set_added(op, 2, 6.0_dp)
    call mass_solve(op, dom, f, a, ierr)
    call t%close(a(1, 2), 1.0_dp/8.0_dp, 1.0e-15_dp, 'added mass: a = f/(m + dm)')
    call t%close_abs(a(2, 2), 0.0_dp, 0.0_dp, 'added mass: fixed dof stays 0')
    call t%close(a(1, 3), 0.25_dp, 1.0e-15_dp, 'added mass: other nodes unchanged')
    call mass_set_added(op, 2, 0.0_dp)
    call mass_solve(op, dom, f, a, ierr)
    call t%close(a(1, 2), 0.5_dp, 1.0e-15_dp, 'added mass 0 restores a = f/m')
    call t%close(op%m_diag(2), 2.0_dp, 0.0_dp, 'm_diag (kinetic energy) unchanged')
  end subroutine added_mass
end program test_contact_omega
