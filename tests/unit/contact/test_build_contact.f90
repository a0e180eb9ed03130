!> build_contact: surfaces, pairs and walls from deck records on a hand-made model (two Q8
!! elements in a row, one clockwise Q8, a half-disc NURBS patch), and the errors it reports.
program test_build_contact
  use ictus_core_kinds, only: dp, pi
  use ictus_core_errors, only: error_count, warning_count
  use ictus_test_check, only: checker_t
  use ictus_elements_types, only: ETYPE_Q8, ETYPE_IGA
  use ictus_io_deck_types, only: deck_t, SURF_ELEMENT, SURF_PATCH, SIDE_XI0, &
      CONTACT_NODE_TO_SEGMENT
  use ictus_solver_model, only: model_t
  use ictus_contact_contact, only: contact_t, PAIR_NODE_TO_SEGMENT, PAIR_WALL
  use ictus_app_build_contact, only: build_contact
  implicit none
  type(checker_t) :: t
  type(deck_t) :: deck
  type(model_t) :: model
  type(contact_t) :: c
  integer :: n0, w0
  call t%start("contact/build_contact")
  call make_model(model)
  call make_deck(deck, .false.)
  n0 = error_count()
  w0 = warning_count()
  call build_contact(deck, model, c)
  call t%equal_int(error_count() - n0, 0, 'good deck: no errors')
  call t%equal_int(warning_count() - w0, 2, 'element 1 listed three times: two warnings')
  call t%equal_int(c%npairs, 2, 'one pair and one wall')
  call t%equal_int(c%surfaces(1)%nseg, 2, 'TOP: two element faces')
  call t%equal_int(c%surfaces(2)%nseg, 1, 'ARC: one span')
  call t%close(sum(c%surfaces(2)%ell), pi, 1.0e-3_dp, 'ARC: 45 degree arc, length ~ pi')
  call t%true(c%pairs(1)%name == 'contact', 'pair name in lower case')
  call t%equal_int(c%pairs(1)%kind, PAIR_NODE_TO_SEGMENT, 'algorithm')
  call t%equal_int(c%pairs(2)%kind, PAIR_WALL, 'wall')
  call t%close(c%pairs(2)%wall_normal(2), 1.0_dp, 1.0e-15_dp, 'wall normal normalised')
  call t%equal_int(c%pairs(1)%npoints, c%surfaces(1)%nsn, 'work arrays set up')
  ! TOP runs counter-clockwise along the top of the row (right to left): element 1's face
  ! from x = 1 to x = 0, element 2's from x = 2 to x = 1, which leads on to element 1's
  call t%close_abs(model%x0(1, c%surfaces(1)%conn(1, 1)), 1.0_dp, 0.0_dp, 'TOP orientation')
  call t%close_abs(model%x0(1, c%surfaces(1)%conn(3, 1)), 0.0_dp, 0.0_dp, 'TOP orientation')
  call t%equal_int(c%surfaces(1)%next(2), 1, 'TOP chained')
  call make_deck(deck, .true.)
  n0 = error_count()
  call build_contact(deck, model, c)
  call t%equal_int(error_count() - n0, 4, 'bad deck: four errors')
  call t%finish()

contains

  !> Nodes: a row of two 1 x 1 Q8 elements (ids 1, 2, nodes 1..13), a clockwise Q8 (id 3)
  !! far away, then the 9 control points of the half-disc patch of doc/iga.md §10.4.
  subroutine make_model(m)
    type(model_t), intent(out) :: m
    real(dp) :: cp(3, 9), cw, tn
    integer :: i
    m%nn = 13 + 8 + 9
    allocate(m%x0(2, m%nn), m%weight(m%nn), m%node_id(m%nn))
    m%weight = 1.0_dp
    m%node_id = [(i, i = 1, m%nn)]
    ! corners bottom 1,2,3 (x = 0,1,2), top 4,5,6; bottom mids 7,8; top mids 9,10;
    ! vertical mids 11,12,13
    m%x0(:, 1:13) = reshape([0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1, 0, 0, 0, 0, 0, 0, 0, 0, &
        0, 0, 0, 0, 0, 0]*1.0_dp, [2, 13])
    m%x0(:, 7) = [0.5_dp, 0.0_dp]
    m%x0(:, 8) = [1.5_dp, 0.0_dp]
    m%x0(:, 9) = [0.5_dp, 1.0_dp]
    m%x0(:, 10) = [1.5_dp, 1.0_dp]
    m%x0(:, 11) = [0.0_dp, 0.5_dp]
    m%x0(:, 12) = [1.0_dp, 0.5_dp]
    m%x0(:, 13) = [2.0_dp, 0.5_dp]
    ! element 3: unit square at (10, 0), nodes 14..21 in clockwise order
    m%x0(:, 14:21) = reshape([10, 0, 10, 1, 11, 1, 11, 0, 10, 0, 11, 1, 11, 1, 10, 0]* &
        1.0_dp, [2, 8])
    m%x0(:, 18:21) = reshape([10.0_dp, 0.5_dp, 10.5_dp, 1.0_dp, 11.0_dp, 0.5_dp, &
        10.5_dp, 0.0_dp], [2, 4])
    cw = cos(pi/8.0_dp)
    tn = tan(pi/8.0_dp)
    cp = reshape([0.0_dp, -4.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 4.0_dp, 1.0_dp, &
        4*tn, -4.0_dp, cw, 2.0_dp, 0.0_dp, 1.0_dp, 4*tn, 4.0_dp, cw, &
        4/sqrt(2.0_dp), -4/sqrt(2.0_dp), 1.0_dp, 4*sqrt(2.0_dp), 0.0_dp, sqrt(0.5_dp), &
        4/sqrt(2.0_dp), 4/sqrt(2.0_dp), 1.0_dp], [3, 9])
    m%npatch = 1
    allocate(m%patches(1), m%patch_offset(1))
    call m%patches(1)%init('DISC', [2, 2], [3, 3], [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
        1.0_dp, 1.0_dp], [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], cp)
    m%patch_offset(1) = 21
    m%x0(:, 22:30) = cp(1:2, :)
    m%weight(22:30) = cp(3, :)
    m%nel = 4
    m%nen_max = 9
    allocate(m%etype(4), m%nen(4), m%conn(9, 4), m%elem_id(4), m%patch(4), m%patch_elem(4))
    m%conn = 0
    m%etype = [ETYPE_Q8, ETYPE_Q8, ETYPE_Q8, ETYPE_IGA]
    m%nen = [8, 8, 8, 9]
    m%conn(1:8, 1) = [1, 2, 5, 4, 7, 12, 9, 11]
    m%conn(1:8, 2) = [2, 3, 6, 5, 8, 13, 10, 12]
    m%conn(1:8, 3) = [(13 + i, i = 1, 8)]
    m%conn(1:9, 4) = [(21 + i, i = 1, 9)]
    m%elem_id = [1, 2, 3, 1]
    m%patch = [0, 0, 0, 1]
    m%patch_elem = [0, 0, 0, 1]
  end subroutine make_model

  !> Surfaces TOP (faces S3 of elements 1 and 2, the second via ELSET ROW, element 1
  !! listed twice) and ARC (patch DISC, XI0); a NODE TO SEGMENT pair and a wall. With `bad`:
  !! also a face of a missing element, a face of the clockwise element 3, a pair with an
  !! undefined surface, and a wall on an undefined surface.
  subroutine make_deck(d, bad)
    type(deck_t), intent(out) :: d
    logical, intent(in) :: bad
    d%n_blocks = 2
    allocate(d%blocks(2))
    d%blocks(1)%etype = ETYPE_Q8
    d%blocks(1)%nen = 8
    d%blocks(1)%elset = 'ROW'
    d%blocks(1)%ids = [1, 2]
    d%blocks(2)%etype = ETYPE_Q8
    d%blocks(2)%nen = 8
    d%blocks(2)%elset = 'INV'
    d%blocks(2)%ids = [3]
    d%n_sets = 0
    allocate(d%sets(0))
    d%n_surfaces = 2
    if (bad) d%n_surfaces = 3
    allocate(d%surfaces(d%n_surfaces))
    d%surfaces(1)%name = 'TOP'
    d%surfaces(1)%kind = SURF_ELEMENT
    d%surfaces(1)%elem = [1, 0, 1]
    d%surfaces(1)%elset = [character(len=64) :: '', 'ROW', '']
    d%surfaces(1)%face = [3, 3, 3]
    d%surfaces(1)%entry_where = [character(len=320) :: 'deck:10', 'deck:11', 'deck:12']
    d%surfaces(1)%where = 'deck:9'
    d%surfaces(2)%name = 'ARC'
    d%surfaces(2)%kind = SURF_PATCH
    d%surfaces(2)%patch = 'disc'
    d%surfaces(2)%side = SIDE_XI0
    d%surfaces(2)%where = 'deck:13'
    if (bad) then
      d%surfaces(3)%name = 'WRONG'
      d%surfaces(3)%kind = SURF_ELEMENT
      d%surfaces(3)%elem = [99, 3]
      d%surfaces(3)%elset = [character(len=64) :: '', '']
      d%surfaces(3)%face = [1, 1]
      d%surfaces(3)%entry_where = [character(len=320) :: 'deck:15', 'deck:16']
      d%surfaces(3)%where = 'deck:14'
    end if
    d%n_pairs = 1
    allocate(d%pairs(1))
    d%pairs(1)%name = 'CONTACT'
    d%pairs(1)%penalty = 1.0e5_dp
    d%pairs(1)%algorithm = CONTACT_NODE_TO_SEGMENT
    d%pairs(1)%first = 'top'
    d%pairs(1)%second = 'ARC'
    if (bad) d%pairs(1)%second = 'MISSING'
    d%pairs(1)%where = 'deck:20'
    d%n_walls = 1
    allocate(d%walls(1))
    d%walls(1)%name = 'FLOOR'
    d%walls(1)%point(1:2) = [0.0_dp, -5.0_dp]
    d%walls(1)%normal(1:2) = [0.0_dp, 3.0_dp]
    d%walls(1)%penalty = 1.0e5_dp
    d%walls(1)%surface = 'ARC'
    if (bad) d%walls(1)%surface = 'NOWHERE'
    d%walls(1)%where = 'deck:22'
  end subroutine make_deck
end program test_build_contact
