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
  use ictus_elements_types, only: ETYPE_IGA, element_kind_t
  use ictus_elements_library, only: element_kind
  use ictus_parallel_env, only: env_is_root
  implicit none
  private
  public :: xdmf_write, xdmf_grid_t, xdmf_block_path

  !> One block of cells: FE elements of one type (/model/elements/<name>/connectivity on
  !! /model/coordinates, fields displacement/velocity), or the NURBS viewing sub-cells (name
  !! 'iga': /viz/iga/cells on /viz/iga/points, fields viz_displacement/viz_velocity).
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
    if (g%etype == ETYPE_IGA) then
      conn = ':/viz/iga/cells'
      geom = ':/viz/iga/points'
      prefix = 'viz_'
    else
      conn = ':/model/elements/'//trim(g%name)//'/connectivity'
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
    write(u, '(a)') '     <Geometry GeometryType="XY">'
    write(u, '(a,i0,a)') '      <DataItem Format="HDF" DataType="Float" Precision="8" '// &
        'Dimensions="', g%npoints, ' 2">'//h5//geom//'</DataItem>'
    write(u, '(a)') '     </Geometry>'
    if (g%displacement) call attribute(u, 'displacement', prefix, h5, sname, g%npoints)
    if (g%velocity) call attribute(u, 'velocity', prefix, h5, sname, g%npoints)
    ! the von Mises stress averaged at the nodes (finite-element blocks: the grid's points are
    ! the model's nodes)
    if (g%etype /= ETYPE_IGA .and. g%mises) then
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
    ! the stress and strain tensors of each element (xx, yy, xy, zz) as 4-component cells
    if (g%stress) call cell_matrix(u, 'stress', block_dataset(g, 'stress'), h5, sname, g%nel)
    if (g%strain) call cell_matrix(u, 'strain', block_dataset(g, 'strain'), h5, sname, g%nel)
    write(u, '(a)') '    </Grid>'
  end subroutine grid

  !> The dataset of the per-element field `name` on the cells of block g.
  function block_dataset(g, name) result(dataset)
    type(xdmf_grid_t), intent(in) :: g
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: dataset
    if (g%etype == ETYPE_IGA) then
      dataset = 'viz_'//name
    else if (g%whole) then
      dataset = name
    else
      dataset = trim(g%name)//'_'//name
    end if
  end function block_dataset

  !> A cell field of 4 components (xx, yy, xy, zz): the (nel, 4) dataset `dataset`.
  subroutine cell_matrix(u, name, dataset, h5, sname, nel)
    integer, intent(in) :: u, nel
    character(len=*), intent(in) :: name, dataset, h5, sname
    write(u, '(a)') '     <Attribute Name="'//name//'" AttributeType="Matrix" Center="Cell">'
    write(u, '(a,i0,a)') '      <DataItem Format="HDF" DataType="Float" Precision="8" '// &
        'Dimensions="', nel, ' 4">'//h5//':/fields/'//sname//'/'//dataset//'</DataItem>'
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

  !> A node vector: the (n, 3) padded copy of the 2-component field.
  subroutine attribute(u, name, prefix, h5, sname, nn)
    integer, intent(in) :: u, nn
    character(len=*), intent(in) :: name, prefix, h5, sname
    write(u, '(a)') '     <Attribute Name="'//name//'" AttributeType="Vector" Center="Node">'
    write(u, '(a,i0,a)') '      <DataItem Format="HDF" DataType="Float" Precision="8" '// &
        'Dimensions="', nn, ' 3">'//h5//':/fields/'//sname//'/'//prefix//name//'_3d</DataItem>'
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
