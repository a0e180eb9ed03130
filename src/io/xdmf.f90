!> The XDMF sidecar that lets ParaView, VisIt and meshio open the field snapshots as a time
!! series. It only points into the HDF5 file; it is rewritten (by rank 0) after every snapshot.
!!
!! What the readers need (doc/results.md, "The XDMF sidecar"):
!! - vectors with 3 components (ParaView's Warp By Vector asserts it): the attributes point to
!!   the padded copies /fields/<step>/[viz_]<field>_3d (z = 0), since meshio cannot evaluate
!!   an XDMF Function over the 2-component datasets;
!! - every real DataItem says DataType="Float" Precision="8" (Xdmf3 reads Precision alone as
!!   float32);
!! - a model with one block is one Uniform grid per step (meshio's time-series reader needs
!!   it); several blocks are a spatial collection per step;
!! - the HDF5 file is named without a directory: readers resolve it from the sidecar's folder.
module ictus_io_xdmf
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: etype_is_nurbs, element_kind_t
  use ictus_elements_library, only: element_kind
  use ictus_parallel_env, only: env_is_root
  implicit none
  private
  public :: xdmf_write, xdmf_grid_t, xdmf_block_path

  !> One block of cells: FE elements of one type (/model/elements/<name>/connectivity on
  !! /model/coordinates, fields displacement/velocity), or the NURBS viewing sub-cells (name
  !! 'iga': /viz/iga/cells on /viz/iga/points, fields viz_displacement/viz_velocity;
  !! quadrilaterals of bivariate patches, etype ETYPE_IGA, or hexahedra of trivariate ones,
  !! ETYPE_IGA3).
  type :: xdmf_grid_t
    character(len=16) :: name = ''
    integer :: etype = 0
    integer :: nel = 0
    integer :: nen = 0
    !> Number of points the cells refer to.
    integer :: npoints = 0
    !> Whether the block holds every element of the model in the model's order (then the
    !! per-element fields are its cell fields).
    logical :: whole = .false.
    !> Which fields the snapshots hold (*OUTPUT, FIELD, VARIABLES=): the attributes of the
    !! others are left out.
    logical :: displacement = .true.
    logical :: velocity = .true.
    logical :: mises = .true.
    logical :: peeq = .true.
    logical :: stress = .true.
    logical :: strain = .false.
    !> The dimension of the model: XY geometry and 2-component vectors (shown through their
    !! padded copies `<name>_3d`) in 2D, XYZ and the vectors themselves in 3D.
    integer :: ndm = 2
    !> Whether the block's XDMF topology orders its nodes otherwise than the deck
    !! (element_kind_t%xdmf_order, C3D27): its cells are then the dataset
    !! `xdmf_connectivity` beside `connectivity`.
    logical :: permuted = .false.
  end type xdmf_grid_t

contains

  !> Writes `path` describing the snapshots `steps`/`times` stored in the HDF5 file `h5path`.
  subroutine xdmf_write(path, h5path, grids, steps, times)
    character(len=*), intent(in) :: path, h5path
    type(xdmf_grid_t), intent(in) :: grids(:)
    integer, intent(in) :: steps(:)
    real(dp), intent(in) :: times(:)
    integer :: u, i, j, ios
    character(len=8) :: sname
    character(len=:), allocatable :: h5
    if (.not. env_is_root()) return
    h5 = basename(h5path)
    open(newunit=u, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) return
    write(u, '(a)') '<?xml version="1.0" ?>'
    write(u, '(a)') '<Xdmf Version="3.0">'
    write(u, '(a)') ' <Domain>'
    write(u, '(a)') '  <Grid Name="ictus" GridType="Collection" CollectionType="Temporal">'
    do i = 1, size(steps)
      write(sname, '(i8.8)') steps(i)
      if (size(grids) == 1) then
        call grid(u, grids(1), 'step '//sname, h5, sname, times(i))
      else
        write(u, '(a)') '   <Grid Name="step '//sname//'" GridType="Collection" '// &
            'CollectionType="Spatial">'
        write(u, '(a,es23.16,a)') '    <Time Value="', times(i), '"/>'
        do j = 1, size(grids)
          call grid(u, grids(j), trim(grids(j)%name), h5, sname)
        end do
        write(u, '(a)') '   </Grid>'
      end if
    end do
    write(u, '(a)') '  </Grid>'
    write(u, '(a)') ' </Domain>'
    write(u, '(a)') '</Xdmf>'
    close(u)
  end subroutine xdmf_write

  !> One Uniform grid `name`: the block `g` at snapshot `sname`, with its own Time when `time`
  !! is given (a grid that is a whole step).
  subroutine grid(u, g, name, h5, sname, time)
    integer, intent(in) :: u
    type(xdmf_grid_t), intent(in) :: g
    character(len=*), intent(in) :: name, h5, sname
    real(dp), intent(in), optional :: time
    character(len=:), allocatable :: conn, geom, prefix
    if (etype_is_nurbs(g%etype)) then
      conn = ':/viz/iga/cells'
      geom = ':/viz/iga/points'
      prefix = 'viz_'
    else
      conn = ':/model/elements/'//trim(g%name)//'/connectivity'
      if (g%permuted) conn = ':/model/elements/'//trim(g%name)//'/xdmf_connectivity'
      geom = ':/model/coordinates'
      prefix = ''
    end if
    write(u, '(a)') '    <Grid Name="'//name//'" GridType="Uniform">'
    if (present(time)) write(u, '(a,es23.16,a)') '     <Time Value="', time, '"/>'
    write(u, '(a,i0,a)') '     <Topology TopologyType="'//topology(g%etype)// &
        '" NumberOfElements="', g%nel, '">'
    write(u, '(a,i0,1x,i0,a)') '      <DataItem Format="HDF" DataType="Int" Dimensions="', &
        g%nel, g%nen, '">'//h5//conn//'</DataItem>'
    write(u, '(a)') '     </Topology>'
    write(u, '(a)') '     <Geometry GeometryType="'//trim(merge('XYZ', 'XY ', g%ndm == 3))//'">'
    write(u, '(a,i0,1x,i0,a)') '      <DataItem Format="HDF" DataType="Float" Precision="8" '// &
        'Dimensions="', g%npoints, g%ndm, '">'//h5//geom//'</DataItem>'
    write(u, '(a)') '     </Geometry>'
    if (g%displacement) call attribute(u, 'displacement', prefix, h5, sname, g%npoints, g%ndm)
    if (g%velocity) call attribute(u, 'velocity', prefix, h5, sname, g%npoints, g%ndm)
    ! the von Mises stress averaged at the nodes (finite-element blocks: the grid's points are
    ! the model's nodes)
    if (.not. etype_is_nurbs(g%etype) .and. g%mises) then
      write(u, '(a)') '     <Attribute Name="mises" AttributeType="Scalar" Center="Node">'
      write(u, '(a,i0,a)') '      <DataItem Format="HDF" DataType="Float" Precision="8" '// &
          'Dimensions="', g%npoints, '">'//h5//':/fields/'//sname//'/nodal_mises</DataItem>'
      write(u, '(a)') '     </Attribute>'
    end if
    ! the per-element von Mises stress and PEEQ as cell fields: the model's datasets for a
    ! block that is the whole model, else the block's own (FE: <type>_mises, NURBS viewing
    ! cells: viz_mises, each cell with its element's value)
    if (g%mises) call cell_scalar(u, 'element_mises', block_dataset(g, 'mises'), h5, sname, &
        g%nel)
    if (g%peeq) call cell_scalar(u, 'peeq', block_dataset(g, 'peeq'), h5, sname, g%nel)
    ! the stress and strain tensors of each element as 4-component cells (xx, yy, xy, zz) in
    ! 2D, 6-component ones (xx, yy, zz, xy, yz, zx) in 3D
    if (g%stress) call cell_matrix(u, 'stress', block_dataset(g, 'stress'), h5, sname, g%nel, &
        merge(6, 4, g%ndm == 3))
    if (g%strain) call cell_matrix(u, 'strain', block_dataset(g, 'strain'), h5, sname, g%nel, &
        merge(6, 4, g%ndm == 3))
    write(u, '(a)') '    </Grid>'
  end subroutine grid

  !> The dataset of the per-element field `name` on the cells of block g.
  function block_dataset(g, name) result(dataset)
    type(xdmf_grid_t), intent(in) :: g
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: dataset
    if (etype_is_nurbs(g%etype)) then
      dataset = 'viz_'//name
    else if (g%whole) then
      dataset = name
    else
      dataset = trim(g%name)//'_'//name
    end if
  end function block_dataset

  !> A cell field of nc components (2D: 4, xx, yy, xy, zz; 3D: 6, xx, yy, zz, xy, yz, zx): the
  !! (nel, nc) dataset `dataset`.
  subroutine cell_matrix(u, name, dataset, h5, sname, nel, nc)
    integer, intent(in) :: u, nel, nc
    character(len=*), intent(in) :: name, dataset, h5, sname
    write(u, '(a)') '     <Attribute Name="'//name//'" AttributeType="Matrix" Center="Cell">'
    write(u, '(a,i0,1x,i0,a)') '      <DataItem Format="HDF" DataType="Float" Precision="8" '// &
        'Dimensions="', nel, nc, '">'//h5//':/fields/'//sname//'/'//dataset//'</DataItem>'
    write(u, '(a)') '     </Attribute>'
  end subroutine cell_matrix

  !> A cell scalar: the per-element dataset `dataset` of the snapshot.
  subroutine cell_scalar(u, name, dataset, h5, sname, nel)
    integer, intent(in) :: u, nel
    character(len=*), intent(in) :: name, dataset, h5, sname
    write(u, '(a)') '     <Attribute Name="'//name//'" AttributeType="Scalar" Center="Cell">'
    write(u, '(a,i0,a)') '      <DataItem Format="HDF" DataType="Float" Precision="8" '// &
        'Dimensions="', nel, '">'//h5//':/fields/'//sname//'/'//dataset//'</DataItem>'
    write(u, '(a)') '     </Attribute>'
  end subroutine cell_scalar

  !> A node vector: the (n, 3) padded copy `<name>_3d` of the 2-component field in 2D, the
  !! (n, 3) field itself in 3D.
  subroutine attribute(u, name, prefix, h5, sname, nn, ndm)
    integer, intent(in) :: u, nn, ndm
    character(len=*), intent(in) :: name, prefix, h5, sname
    character(len=:), allocatable :: dataset
    dataset = prefix//name//'_3d'
    if (ndm == 3) dataset = prefix//name
    write(u, '(a)') '     <Attribute Name="'//name//'" AttributeType="Vector" Center="Node">'
    write(u, '(a,i0,a)') '      <DataItem Format="HDF" DataType="Float" Precision="8" '// &
        'Dimensions="', nn, ' 3">'//h5//':/fields/'//sname//'/'//dataset//'</DataItem>'
    write(u, '(a)') '     </Attribute>'
  end subroutine attribute

  !> The sidecar of one block of a model with several: `xdmf_path` with `.<name>` before
  !! `.xdmf` (results.xdmf -> results.q8.xdmf), for readers that take one mesh per file.
  function xdmf_block_path(xdmf_path, name) result(path)
    character(len=*), intent(in) :: xdmf_path, name
    character(len=:), allocatable :: path
    integer :: k
    k = index(xdmf_path, '.xdmf', back=.true.)
    if (k > 0 .and. k == len(xdmf_path) - 4) then
      path = xdmf_path(1:k - 1)//'.'//trim(name)//'.xdmf'
    else
      path = xdmf_path//'.'//trim(name)
    end if
  end function xdmf_block_path

  !> XDMF topology name of an element type (element_kind_t%xdmf).
  function topology(etype) result(name)
    integer, intent(in) :: etype
    character(len=:), allocatable :: name
    type(element_kind_t) :: k
    k = element_kind(etype)
    name = trim(k%xdmf)
    if (len(name) == 0) name = 'Polyvertex'
  end function topology

  !> File name without its directory (the sidecar sits next to the HDF5 file).
  function basename(path) result(name)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: name
    integer :: k
    k = index(path, '/', back=.true.)
    name = path(k + 1:)
  end function basename
end module ictus_io_xdmf
