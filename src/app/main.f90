program ictus
  implicit none
end program ictus
