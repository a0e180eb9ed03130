!> The 3D part of a model's contact (doc/contact.md §9): the surfaces of quadrilateral faces,
!! the TWO HALF PASS pairs and rigid walls between them, their forces on the predicted
!! coordinates and the predictor-corrector stability ratio. `ictus_contact_contact` holds one
!! of these in a 3D model and calls it where the 2D model calls its segment routines.
module ictus_contact_contact3d
  use ictus_core_kinds, only: dp, str_len
  use ictus_contact_face3d, only: surface3d_t, face_shape, projection3d_t, project3d, &
      P3_INTERIOR, P3_CORNER, MAX_FACE_NODES
  use ictus_contact_pair3d, only: pair3d_t, pair3d_setup, pair3d_grids, two_half_pass3d, &
      wall3d, node_to_surface3d
  use ictus_contact_search3d, only: grid3_query
  implicit none
  private
  public :: contact3d_t, contact3d_setup, contact3d_pair_forces, contact3d_ratio

  type :: contact3d_t
    !> Surfaces (faces of hexahedra) and the pairs (walls: second = 0), in the order of the
    !! owner's pairs.
    integer :: nsurf = 0
    type(surface3d_t), allocatable :: surfaces(:)
    !> The surfaces' names (for messages).
    character(len=str_len), allocatable :: names(:)
    type(pair3d_t), allocatable :: pairs(:)
  end type contact3d_t

contains

  !> Sizes the work arrays of every pair (surfaces and pairs defined).
  subroutine contact3d_setup(c)
    type(contact3d_t), intent(inout) :: c
    integer :: k, s2
    do k = 1, size(c%pairs)
      s2 = c%pairs(k)%second
      ! a wall (second = 0) passes its own surface twice
      call pair3d_setup(c%pairs(k), c%surfaces(c%pairs(k)%first), &
          c%surfaces(merge(s2, c%pairs(k)%first, s2 > 0)), s2 == 0)
    end do
  end subroutine contact3d_setup

  !> Forces of pair k on the coordinates x (3, nn), accumulated into fc (3, nn); xs, ps
  !! (the first surface's Gauss points and pressures) are filled.
  subroutine contact3d_pair_forces(c, k, x, fc, xs, ps)
    type(contact3d_t), intent(inout) :: c
    integer, intent(in) :: k
    real(dp), intent(in) :: x(:,:)
    real(dp), intent(inout) :: fc(:,:), xs(:,:), ps(:)
    associate (p => c%pairs(k))
      if (p%second == 0) then
        call wall3d(p, c%surfaces(p%first), x, fc, xs, ps)
      else if (p%nts) then
        call node_to_surface3d(p, c%surfaces(p%first), c%surfaces(p%second), x, fc, xs, ps)
      else
        call two_half_pass3d(p, c%surfaces(p%first), c%surfaces(p%second), x, fc, xs, ps)
      end if
    end associate
  end subroutine contact3d_pair_forces

  !> The largest contact ratio r = dt^2 eps (l_s/m_s + l_m/m_m) of pair k on x (3, nn) with
  !! the lumped masses m_diag (nn) (doc/contact.md §9.4): over the nodes of each surface
  !! acting as slave (NODE TO SEGMENT: the first only), l_s/m_s of the node (l: the
  !! row-sum weight ell_row; NODE TO SEGMENT: the nodal area) and, against
  !! another surface, l_m/m_m = sum_B |N_B| l_B/m_B at the node's closest point on the other
  !! surface (its largest l/m where the node has no closest point); a wall has the slave term
  !! only. gs, gm: the node of the largest r and its master node of largest |N_B| (0: none).
  !! r is huge where a mass is not positive.
  subroutine contact3d_ratio(c, k, eps, x, m_diag, dt, r, gs, gm)
    type(contact3d_t), intent(inout) :: c
    integer, intent(in) :: k
    real(dp), intent(in) :: eps, x(:,:), m_diag(:), dt
    real(dp), intent(out) :: r
    integer, intent(out) :: gs, gm
    r = 0.0_dp
    gs = 0
    gm = 0
    associate (p => c%pairs(k))
      if (p%second == 0) then
        call side_ratio(p, c%surfaces(p%first), c%surfaces(p%first), .false., eps, x, &
            m_diag, dt, r, gs, gm)
      else
        call pair3d_grids(p, c%surfaces(p%first), c%surfaces(p%second), x)
        call side_ratio(p, c%surfaces(p%first), c%surfaces(p%second), .false., eps, x, &
            m_diag, dt, r, gs, gm, .true.)
        ! NODE TO SEGMENT: only the first surface's nodes are slaves
        if (.not. p%nts) call side_ratio(p, c%surfaces(p%second), c%surfaces(p%first), &
            .true., eps, x, m_diag, dt, r, gs, gm, .true.)
      end if
    end associate
  end subroutine contact3d_ratio

  !> The ratios of the nodes of `slave` (against `master` when has_master; its grid: the
  !! pair's second grid, or the first when flip); the largest kept in r, gs, gm.
  subroutine side_ratio(p, slave, master, flip, eps, x, m_diag, dt, r, gs, gm, has_master)
    type(pair3d_t), intent(inout) :: p
    type(surface3d_t), intent(in) :: slave, master
    logical, intent(in) :: flip
    real(dp), intent(in) :: eps, x(:,:), m_diag(:), dt
    real(dp), intent(inout) :: r
    integer, intent(inout) :: gs, gm
    logical, intent(in), optional :: has_master
    type(projection3d_t) :: pr
    real(dp) :: rs, rm, rm_all, rr, nr(MAX_FACE_NODES), dnr(2, MAX_FACE_NODES), rb, best
    integer :: a, g, b, gb, gb_all, ncand
    logical :: against
    against = .false.
    if (present(has_master)) against = has_master
    rm_all = 0.0_dp
    gb_all = 0
    if (against) then
      do b = 1, master%nsn
        rb = over_m(master%ell_row(b), m_diag(master%nodes(b)))
        if (rb > rm_all .or. gb_all == 0) then
          rm_all = rb
          gb_all = master%nodes(b)
        end if
      end do
    end if
    do a = 1, slave%nsn
      g = slave%nodes(a)
      rs = over_m(merge(slave%area(a), slave%ell_row(a), p%nts), m_diag(g))
      rm = 0.0_dp
      gb = 0
      if (against) then
        if (flip) then
          call grid3_query(p%grid_first, x(:, g), p%cand, ncand)
        else
          call grid3_query(p%grid_second, x(:, g), p%cand, ncand)
        end if
        call project3d(master, x, x(:, g), p%cand, ncand, pr)
        if (pr%status == P3_INTERIOR .or. pr%status == P3_CORNER) then
          call face_shape(master, pr%face, pr%xi, nr, dnr)
          best = -1.0_dp
          do b = 1, master%nen(pr%face)
            rb = over_m(master%ell_row(master%lnode(b, pr%face)), &
                m_diag(master%conn(b, pr%face)))
            if (rb >= huge(1.0_dp)) then
              rm = huge(1.0_dp)
            else if (rm < huge(1.0_dp)) then
              rm = rm + abs(nr(b))*rb
            end if
            if (abs(nr(b)) > best) then
              best = abs(nr(b))
              gb = master%conn(b, pr%face)
            end if
          end do
        else
          rm = rm_all
          gb = gb_all
        end if
      end if
      if (rs >= huge(1.0_dp) .or. rm >= huge(1.0_dp)) then
        rr = huge(1.0_dp)
      else
        rr = dt*dt*eps*(rs + rm)
      end if
      if (rr > r .or. gs == 0) then
        r = rr
        gs = g
        gm = gb
      end if
    end do
  end subroutine side_ratio

  !> l/m, or huge for a non-positive mass m.
  pure real(dp) function over_m(ell, m)
    real(dp), intent(in) :: ell, m
    if (m <= 0.0_dp) then
      over_m = huge(1.0_dp)
    else
      over_m = ell/m
    end if
  end function over_m
end module ictus_contact_contact3d
